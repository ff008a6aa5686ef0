#include "sim/EmbreeCaster.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace ambler::sim {

struct EmbreeCaster::Scene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  Eigen::Vector3d offset{0, 0, 0};  // subtracted from vertices: floats keep mm far from 0

  ~Scene() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

EmbreeCaster::EmbreeCaster(const Terrain& terrain, const Box2& area, double spacing)
    : terrain_(terrain), scene_(std::make_unique<Scene>()) {
  const Box2 e = terrain.extent();
  const Box2 box{std::max(area.x_min, e.x_min), std::max(area.y_min, e.y_min),
                 std::min(area.x_max, e.x_max), std::min(area.y_max, e.y_max)};
  if (!(spacing > 0) || box.width() <= 0 || box.height() <= 0)
    throw std::invalid_argument("EmbreeCaster: empty area or non-positive spacing");
  const int cols = int(std::floor(box.width() / spacing)) + 1;
  const int rows = int(std::floor(box.height() / spacing)) + 1;
  const Eigen::Vector2d centre(0.5 * (box.x_min + box.x_max), 0.5 * (box.y_min + box.y_max));
  scene_->offset = {centre.x(), centre.y(), terrain.height(centre.x(), centre.y())};
  if (!std::isfinite(scene_->offset.z())) scene_->offset.z() = 0.0;

  scene_->device = rtcNewDevice(nullptr);
  if (!scene_->device) throw std::runtime_error("Embree: no device");
  scene_->scene = rtcNewScene(scene_->device);
  RTCGeometry mesh = rtcNewGeometry(scene_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                               std::size_t(rows) * cols));
  std::vector<bool> valid(std::size_t(rows) * cols);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double x = box.x_min + c * spacing, y = box.y_min + r * spacing;
      const double z = terrain.height(x, y);
      const std::size_t i = std::size_t(r) * cols + c;
      valid[i] = std::isfinite(z);
      vertices[3 * i + 0] = float(x - scene_->offset.x());
      vertices[3 * i + 1] = float(y - scene_->offset.y());
      vertices[3 * i + 2] = float(valid[i] ? z - scene_->offset.z() : 0.0);
    }
  std::vector<unsigned> triangles;
  for (int r = 0; r + 1 < rows; ++r)
    for (int c = 0; c + 1 < cols; ++c) {
      const unsigned a = unsigned(r * cols + c), b = a + 1, d = a + unsigned(cols), f = d + 1;
      if (!(valid[a] && valid[b] && valid[d] && valid[f])) continue;
      triangles.insert(triangles.end(), {a, b, f, a, f, d});
    }
  auto* index = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                              3 * sizeof(unsigned), triangles.size() / 3));
  std::copy(triangles.begin(), triangles.end(), index);
  rtcCommitGeometry(mesh);
  rtcAttachGeometry(scene_->scene, mesh);
  rtcReleaseGeometry(mesh);
  rtcSetSceneBuildQuality(scene_->scene, RTC_BUILD_QUALITY_HIGH);
  rtcCommitScene(scene_->scene);
  if (rtcGetDeviceError(scene_->device) != RTC_ERROR_NONE)
    throw std::runtime_error("Embree: cannot build the scene (" +
                             std::to_string(triangles.size() / 3) + " triangles)");
}

EmbreeCaster::~EmbreeCaster() = default;

std::optional<double> EmbreeCaster::cast(const Eigen::Vector3d& origin,
                                         const Eigen::Vector3d& direction, double max_range) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit hit{};
  const Eigen::Vector3d o = origin - scene_->offset;
  hit.ray.org_x = float(o.x());
  hit.ray.org_y = float(o.y());
  hit.ray.org_z = float(o.z());
  hit.ray.dir_x = float(direction.x());
  hit.ray.dir_y = float(direction.y());
  hit.ray.dir_z = float(direction.z());
  hit.ray.tnear = 0.0f;
  hit.ray.tfar = float(max_range);
  hit.ray.mask = 0xFFFFFFFFu;
  hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_->scene, &context, &hit);
  if (hit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  return double(hit.ray.tfar);
}

}  // namespace ambler::sim
