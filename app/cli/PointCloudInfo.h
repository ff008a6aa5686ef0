#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

namespace ambler::cli {

// Describes a PCD point cloud (fields, size, bounds). This header keeps PCL
// out of its callers; PCL's templates stay in PointCloudInfo.cpp.
nlohmann::json describePointCloud(const std::filesystem::path& pcd_path);

}  // namespace ambler::cli
