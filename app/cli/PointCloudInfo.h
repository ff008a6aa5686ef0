#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

namespace ambler::cli {

// Describes a PCD point cloud (fields, size, bounds); io::readPcd reads it.
nlohmann::json describePointCloud(const std::filesystem::path& pcd_path);

}  // namespace ambler::cli
