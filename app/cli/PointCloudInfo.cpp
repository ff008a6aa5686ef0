#include "cli/PointCloudInfo.h"

#include <pcl/PCLPointCloud2.h>
#include <pcl/common/point_tests.h>
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <limits>

#include "io/FormatError.h"
#include "io/PcdHeader.h"

namespace ambler::cli {

nlohmann::json describePointCloud(const std::filesystem::path& pcd_path) {
  io::checkPcd(pcd_path, false);  // before PCL, which crashes on some malformed files
  pcl::PCLPointCloud2 cloud;
  pcl::PCDReader reader;
  if (reader.read(pcd_path.string(), cloud) < 0)
    throw io::FormatError("PCD '" + pcd_path.string() + "': malformed or truncated");
  nlohmann::json fields = nlohmann::json::array();
  bool has_xyz[3] = {false, false, false};
  for (const auto& f : cloud.fields) {
    fields.push_back(f.name);
    for (int i = 0; i < 3; ++i) has_xyz[i] |= f.name == std::string(1, char('x' + i));
  }
  nlohmann::json out = {{"type", "point_cloud"},
                        {"format", "pcd"},
                        {"points", std::size_t(cloud.width) * cloud.height},
                        {"width", cloud.width},
                        {"height", cloud.height},
                        {"fields", fields},
                        {"is_dense", bool(cloud.is_dense)}};
  if (!(has_xyz[0] && has_xyz[1] && has_xyz[2])) return out;

  pcl::PointCloud<pcl::PointXYZ> xyz;
  pcl::fromPCLPointCloud2(cloud, xyz);
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
  Eigen::Vector3f hi = -lo;
  std::size_t finite = 0;
  for (const auto& p : xyz) {
    if (!pcl::isFinite(p)) continue;
    lo = lo.cwiseMin(p.getVector3fMap());
    hi = hi.cwiseMax(p.getVector3fMap());
    ++finite;
  }
  out["finite_points"] = finite;
  if (finite > 0)
    out["bounds_m"] = {{"min", {lo.x(), lo.y(), lo.z()}}, {"max", {hi.x(), hi.y(), hi.z()}}};
  return out;
}

}  // namespace ambler::cli
