#include "sim/ScannerSim.h"

#include <random>

#include "core/Angles.h"
#include "io/Json.h"

namespace ambler::sim {

Eigen::Isometry3d ScannerModel::mountPose(const Eigen::Vector3d& ground, double heading) const {
  // The sensor frame's y is the boresight and z is up (eq. 1); tilting the
  // boresight down by `tilt` is a rotation of -tilt about the sensor's x.
  return Eigen::Translation3d(ground + Eigen::Vector3d(0, 0, mount_height)) *
         Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(-tilt, Eigen::Vector3d::UnitX());
}

ScannerModel readScannerModel(const std::filesystem::path& json_path) {
  const auto json = io::readJsonFile(json_path);
  const io::JsonFields f(json, "scanner model '" + json_path.string() + "'");
  ScannerModel m;
  const int rows = f.integer("rows"), cols = f.integer("cols");
  if (rows <= 0 || cols <= 0 || rows > 8192 || cols > 8192)
    f.fail("rows", "and cols must be in 1..8192");
  const double vfov = f.number("vertical_fov_deg"), hfov = f.number("horizontal_fov_deg");
  if (vfov <= 0 || vfov >= 180) f.fail("vertical_fov_deg", "must be in (0, 180)");
  if (hfov <= 0 || hfov >= 180) f.fail("horizontal_fov_deg", "must be in (0, 180)");
  m.geometry = sensor::ScanGeometry::symmetric(rows, cols, vfov * kDeg, hfov * kDeg);
  m.range_sigma_k = f.number("range_sigma_k");
  if (m.range_sigma_k < 0) f.fail("range_sigma_k", "must be >= 0");
  m.max_range = f.number("max_range_m");
  if (m.max_range <= 0) f.fail("max_range_m", "must be positive");
  const auto mount = f.object("mount");
  m.mount_height = mount.number("height_m");
  m.tilt = mount.number("tilt_deg") * kDeg;
  return m;
}

sensor::RangeImage simulateScan(const RayCaster& caster, const ScannerModel& model,
                                const Eigen::Isometry3d& sensor_to_world,
                                std::uint64_t noise_seed) {
  sensor::RangeImage image;
  image.geometry = model.geometry;
  image.sensor_to_world = sensor_to_world;
  image.range_sigma_k = model.range_sigma_k;
  const auto& g = model.geometry;
  image.range.assign(std::size_t(g.rows) * g.cols, 0.0f);
  const Eigen::Vector3d origin = sensor_to_world.translation();
  const Eigen::Matrix3d rotation = sensor_to_world.linear();

#pragma omp parallel for schedule(dynamic, 4)
  for (int r = 0; r < g.rows; ++r) {
    std::mt19937_64 rng(noise_seed * 0x9E3779B97F4A7C15ULL + std::uint64_t(r));
    std::normal_distribution<double> unit_normal;
    for (int c = 0; c < g.cols; ++c) {
      const Eigen::Vector3d dir = rotation * sensor::toCartesian({1.0, g.phi(r), g.theta(c)});
      const auto hit = caster.cast(origin, dir, model.max_range);
      if (!hit) continue;
      const double noisy = *hit + sensor::rangeSigma(*hit, model.range_sigma_k) * unit_normal(rng);
      image.range[std::size_t(r) * g.cols + c] = float(std::max(noisy, 1e-3));
    }
  }
  return image;
}

Box2 groundFootprint(const ScannerModel& model, const Eigen::Isometry3d& sensor_to_world,
                     double ground_z) {
  const auto& g = model.geometry;
  const Eigen::Vector3d o = sensor_to_world.translation();
  Box2 box{o.x(), o.y(), o.x(), o.y()};
  auto include = [&](double row, double col) {
    const Eigen::Vector3d d =
        sensor_to_world.linear() * sensor::toCartesian({1.0, g.phi(row), g.theta(col)});
    double t = model.max_range;
    if (d.z() < 0) t = std::min(t, (ground_z - o.z()) / d.z());
    const Eigen::Vector3d p = o + t * d;
    box = {std::min(box.x_min, p.x()), std::min(box.y_min, p.y()), std::max(box.x_max, p.x()),
           std::max(box.y_max, p.y())};
  };
  for (int r = 0; r < g.rows; ++r) include(r, 0), include(r, g.cols - 1);
  for (int c = 0; c < g.cols; ++c) include(0, c), include(g.rows - 1, c);
  return box;
}

VisibilityTruth computeVisibility(const FirstHit& caster, const ScannerModel& model,
                                  const Eigen::Isometry3d& sensor_to_world, const GridSpec& grid) {
  VisibilityTruth truth{grid, io::FloatImage(grid.rows, grid.cols),
                        io::ByteImage(grid.rows, grid.cols)};
  const Eigen::Vector3d origin = sensor_to_world.translation();
  const Eigen::Isometry3d world_to_sensor = sensor_to_world.inverse();
  const auto& terrain = caster.terrain();

#pragma omp parallel for schedule(dynamic, 4)
  for (int r = 0; r < grid.rows; ++r) {
    for (int c = 0; c < grid.cols; ++c) {
      const auto xy = grid.cellCenter(r, c);
      const double z = terrain.height(xy.x(), xy.y());
      truth.height(r, c) = float(z);
      auto state = Visibility::kOutsideView;
      if (std::isfinite(z)) {
        const Eigen::Vector3d ground(xy.x(), xy.y(), z);
        const auto s = sensor::toSpherical(world_to_sensor * ground);
        if (s.rho <= model.max_range && model.geometry.covers(s.phi, s.theta)) {
          // Seen when the first hit towards the point is the point itself;
          // the tolerance absorbs the bisection on grazing rays.
          const Eigen::Vector3d dir = (ground - origin) / s.rho;
          const auto hit = caster.cast(origin, dir, s.rho + 1.0);
          const double tolerance = 0.02 + 1e-3 * s.rho;
          state = (hit && *hit < s.rho - tolerance) ? Visibility::kOccluded : Visibility::kVisible;
        }
      }
      truth.state(r, c) = static_cast<unsigned char>(state);
    }
  }
  return truth;
}

}  // namespace ambler::sim
