#include <algorithm>
#include <filesystem>
#include <memory>

#include "cli/Arguments.h"
#include "cli/Commands.h"
#include "cli/PointCloudInfo.h"
#include "sensor/RangeImageFile.h"
#include "sensor/StriperImageFile.h"

namespace ambler::cli {

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

nlohmann::json rangeStatistics(std::vector<float> values) {
  std::erase_if(values, [](float v) { return !(std::isfinite(v) && v > 0.0f); });
  if (values.empty()) return nullptr;
  const auto mid = values.begin() + std::ptrdiff_t(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  return {{"min", *lo}, {"median", *mid}, {"max", *hi}};
}

nlohmann::json describeRangeImage(const std::filesystem::path& path) {
  const auto image = sensor::readRangeImage(path);
  const auto& g = image.geometry;
  const auto p = image.sensor_to_world.translation();
  return {{"type", "range_image"},
          {"model", "spherical_polar"},
          {"rows", g.rows},
          {"cols", g.cols},
          {"returns", image.returnCount()},
          {"no_return", g.rows * g.cols - image.returnCount()},
          {"range_m", rangeStatistics(image.range)},
          {"phi_deg", {g.phi(0) * kRadToDeg, g.phi(g.rows - 1) * kRadToDeg}},
          {"theta_deg", {g.theta(0) * kRadToDeg, g.theta(g.cols - 1) * kRadToDeg}},
          {"range_sigma_k", image.range_sigma_k},
          {"sensor_position_m", {p.x(), p.y(), p.z()}},
          {"has_reflectance", !image.reflectance.empty()}};
}

nlohmann::json describeStriper(const std::filesystem::path& folder) {
  const auto image = sensor::readStriperImage(folder);
  return {{"type", "striper_image"},
          {"rows", image.rows()},
          {"cols", image.cols()},
          {"points", image.pointCount()},
          {"no_measurement", image.rows() * image.cols() - image.pointCount()}};
}

}  // namespace

void addInfo(CLI::App& app) {
  auto file = std::make_shared<std::string>();
  auto* cmd = app.add_subcommand(
      "info", "Describe a range image (.tif + .json), a striper folder or a point cloud (.pcd)");
  cmd->add_option("FILE", *file, "file or folder")->required();
  cmd->callback([file] {
    const std::filesystem::path path(*file);
    if (std::filesystem::is_directory(path) && sensor::isStriperFolder(path))
      printJson(describeStriper(path));
    else if (path.extension() == ".pcd")
      printJson(describePointCloud(path));
    else if (path.extension() == ".tif" || path.extension() == ".tiff")
      printJson(describeRangeImage(path));
    else
      throw std::invalid_argument("'" + path.string() +
                                  "': unknown kind; expected a range image .tif with its .json "
                                  "sidecar, a striper folder or a .pcd point cloud");
  });
}

}  // namespace ambler::cli
