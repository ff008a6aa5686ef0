#include "sim/StriperSim.h"

#include <cmath>
#include <limits>
#include <random>

namespace ambler::sim {

sensor::PinholeCamera StriperModel::camera() const {
  sensor::PinholeCamera cam;
  cam.rows = rows;
  cam.cols = cols;
  cam.fx = cam.fy = 0.5 * cols / std::tan(0.5 * horizontal_fov);
  cam.cx = 0.5 * (cols - 1);
  cam.cy = 0.5 * (rows - 1);
  // Camera z towards the target, x to the image's right, y down the image.
  const Eigen::Vector3d z = (look_at - camera_position).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  cam.camera_to_world.linear() << x, y, z;
  cam.camera_to_world.translation() = camera_position;
  return cam;
}

namespace {

Eigen::Vector3d surfaceNormal(const Terrain& terrain, double x, double y) {
  const double h = 5e-4;
  const double dzdx = (terrain.height(x + h, y) - terrain.height(x - h, y)) / (2 * h);
  const double dzdy = (terrain.height(x, y + h) - terrain.height(x, y - h)) / (2 * h);
  return Eigen::Vector3d(-dzdx, -dzdy, 1.0).normalized();
}

double albedo(int feature) { return feature < 0 ? 0.7 : 0.3 + 0.1 * (feature % 3); }

}  // namespace

StriperScene simulateStriper(const ProceduralTerrain& terrain, const RayCaster& caster,
                             const StriperModel& model, std::uint64_t noise_seed) {
  StriperScene scene;
  auto& img = scene.image;
  img.camera = model.camera();
  img.projector_position = model.projector_position;
  const std::size_t n = std::size_t(model.rows) * model.cols;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  img.x.assign(n, nan);
  img.y.assign(n, nan);
  img.z.assign(n, nan);
  img.intensity.assign(n, 0.0f);
  scene.labels = io::ByteImage(model.rows, model.cols, kLabelNothing);
  const Eigen::Vector3d eye = model.camera_position;
  const double reach = 10.0 * (model.look_at - eye).norm();

#pragma omp parallel for schedule(dynamic, 4)
  for (int r = 0; r < model.rows; ++r) {
    std::mt19937_64 rng(noise_seed * 0x9E3779B97F4A7C15ULL + std::uint64_t(r));
    std::normal_distribution<double> unit_normal;
    for (int c = 0; c < model.cols; ++c) {
      const Eigen::Vector3d dir = img.camera.rayInWorld(r, c);
      const auto t = caster.cast(eye, dir, reach);
      if (!t) continue;
      const Eigen::Vector3d p = eye + *t * dir;
      const int feature = terrain.featureAt(p.x(), p.y());
      scene.labels(r, c) = feature < 0 ? kLabelGround : static_cast<unsigned char>(feature + 1);
      const auto i = img.index(r, c);

      const Eigen::Vector3d to_projector = model.projector_position - p;
      const double light_distance = to_projector.norm();
      const auto blocker = caster.cast(model.projector_position, -to_projector / light_distance,
                                       light_distance + 1.0);
      const bool lit = !blocker || *blocker > light_distance - 2e-3;
      const double shade =
          std::max(0.0, surfaceNormal(terrain, p.x(), p.y()).dot(to_projector) / light_distance);
      img.intensity[i] = float(albedo(feature) * (0.05 + (lit ? 0.95 * shade : 0.0)));
      if (!lit) continue;  // range shadow: the striper measures nothing here
      const Eigen::Vector3d measured = eye + (*t + model.noise_sigma * unit_normal(rng)) * dir;
      img.x[i] = float(measured.x());
      img.y[i] = float(measured.y());
      img.z[i] = float(measured.z());
    }
  }
  return scene;
}

}  // namespace ambler::sim
