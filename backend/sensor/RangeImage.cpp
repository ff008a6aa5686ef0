#include "sensor/RangeImage.h"

#include "core/Pose.h"

namespace ambler::sensor {

int RangeImage::returnCount() const {
  int n = 0;
  for (float v : range) n += (std::isfinite(v) && v > 0.0f) ? 1 : 0;
  return n;
}

std::vector<Eigen::Vector3d> RangeImage::pointsInSensor() const {
  std::vector<Eigen::Vector3d> out;
  out.reserve(std::size_t(returnCount()));
  for (int r = 0; r < rows(); ++r)
    for (int c = 0; c < cols(); ++c)
      if (hasReturn(r, c)) out.push_back(pointInSensor(r, c));
  return out;
}

std::vector<Eigen::Vector3d> RangeImage::pointsInWorld() const {
  auto out = pointsInSensor();
  for (auto& p : out) p = sensor_to_world * p;
  return out;
}

std::string findProblem(const RangeImage& image) {
  const auto& g = image.geometry;
  if (g.rows <= 0 || g.cols <= 0) return "rows and cols must be positive";
  const std::size_t n = std::size_t(g.rows) * g.cols;
  if (image.range.size() != n)
    return "range data holds " + std::to_string(image.range.size()) + " values, expected " +
           std::to_string(n) + " (rows x cols)";
  if (!image.reflectance.empty() && image.reflectance.size() != n)
    return "reflectance size differs from the range image size";
  for (double v : {g.phi_first, g.phi_step, g.theta_first, g.theta_step})
    if (!std::isfinite(v)) return "scan angles must be finite";
  if (g.phi_step == 0.0 || g.theta_step == 0.0) return "angular steps must be non-zero";
  // Scanlines beyond one turn would be the same scanlines again.
  if (std::abs(g.phi_first) > 2 * M_PI || std::abs(g.phi(g.rows - 1)) > 2 * M_PI)
    return "phi must stay within -360..360 degrees";
  const double half_pi = M_PI / 2;
  if (std::abs(g.theta(0)) >= half_pi || std::abs(g.theta(g.cols - 1)) >= half_pi)
    return "theta must stay inside (-90, 90) degrees for eq. 1 to be invertible";
  if (!std::isfinite(image.range_sigma_k) || image.range_sigma_k < 0.0)
    return "range_sigma_k must be finite and non-negative";
  if (!isRigid(image.sensor_to_world.matrix())) return "sensor_to_world is not a rigid transform";
  for (std::size_t i = 0; i < n; ++i) {
    const float v = image.range[i];
    if (v < 0.0f || std::isinf(v))
      return "range at row " + std::to_string(i / g.cols) + ", col " + std::to_string(i % g.cols) +
             " is " + std::to_string(v) + "; ranges must be >= 0 (0 or NaN = no return)";
  }
  return {};
}

}  // namespace ambler::sensor
