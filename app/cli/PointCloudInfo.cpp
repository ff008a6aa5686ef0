#include "cli/PointCloudInfo.h"

#include <array>
#include <cmath>
#include <limits>

#include "io/Pcd.h"

namespace ambler::cli {

nlohmann::json describePointCloud(const std::filesystem::path& pcd_path) {
  const auto cloud = io::readPcd(pcd_path, false);
  const auto& h = cloud.header;
  nlohmann::json fields = nlohmann::json::array();
  for (const auto& f : h.fields) fields.push_back(f.name);
  nlohmann::json out = {{"type", "point_cloud"},  {"format", "pcd"},    {"points", h.points},
                        {"width", h.width},       {"height", h.height}, {"fields", fields},
                        {"is_dense", cloud.dense}};
  const std::array<int, 3> axes = {h.column("x"), h.column("y"), h.column("z")};
  if (axes[0] < 0 || axes[1] < 0 || axes[2] < 0) return out;

  std::array<double, 3> lo, hi;
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  std::size_t finite = 0;
  for (std::uint64_t i = 0; i < h.points; ++i) {
    std::array<double, 3> p;
    for (int a = 0; a < 3; ++a) p[a] = cloud.at(i, axes[a]);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
    ++finite;
  }
  out["finite_points"] = finite;
  if (finite > 0) out["bounds_m"] = {{"min", lo}, {"max", hi}};
  return out;
}

}  // namespace ambler::cli
