#include "sensor/StriperImage.h"

#include "core/Pose.h"

namespace ambler::sensor {

int StriperImage::pointCount() const {
  int n = 0;
  for (float v : x) n += std::isfinite(v) ? 1 : 0;
  return n;
}

std::string findProblem(const StriperImage& image) {
  const auto& cam = image.camera;
  if (cam.rows <= 0 || cam.cols <= 0) return "rows and cols must be positive";
  const std::size_t n = std::size_t(cam.rows) * cam.cols;
  for (const auto* plane : {&image.x, &image.y, &image.z, &image.intensity})
    if (plane->size() != n) return "X, Y, Z and intensity must each hold rows x cols values";
  if (!(cam.fx > 0.0) || !(cam.fy > 0.0) || !std::isfinite(cam.fx) || !std::isfinite(cam.fy))
    return "focal lengths fx, fy must be positive and finite";
  if (!std::isfinite(cam.cx) || !std::isfinite(cam.cy)) return "principal point must be finite";
  if (!isRigid(cam.camera_to_world.matrix())) return "camera_to_world is not a rigid transform";
  if (!image.projector_position.allFinite()) return "projector_position must be finite";
  for (std::size_t i = 0; i < n; ++i) {
    const int finite =
        std::isfinite(image.x[i]) + std::isfinite(image.y[i]) + std::isfinite(image.z[i]);
    if (finite != 0 && finite != 3)
      return "pixel " + std::to_string(i / cam.cols) + "," + std::to_string(i % cam.cols) +
             " has a partial X/Y/Z triple (some NaN, some not)";
  }
  return {};
}

}  // namespace ambler::sensor
