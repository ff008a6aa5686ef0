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

TerrainDescription withoutRocks(const TerrainDescription& d, std::vector<int>& kept) {
  TerrainDescription out = d;
  out.features.clear();
  for (std::size_t i = 0; i < d.features.size(); ++i)
    if (!std::holds_alternative<Rock>(d.features[i])) {
      out.features.push_back(d.features[i]);
      kept.push_back(int(i));
    }
  return out;
}

// Entry into the superquadric along the ray within [0, max_t]: marched in
// 0.5 mm steps inside its bounding sphere, then bisected.
std::optional<double> enterSuperquadric(const Superquadric& s, const Eigen::Vector3d& o,
                                        const Eigen::Vector3d& d, double max_t) {
  const Eigen::Vector3d oc = o - s.pose.translation();
  const double radius = s.size.norm(), b = oc.dot(d);
  const double disc = b * b - (oc.squaredNorm() - radius * radius);
  if (disc <= 0) return std::nullopt;
  const double t0 = std::max(0.0, -b - std::sqrt(disc)), t1 = std::min(max_t, -b + std::sqrt(disc));
  constexpr double kStep = 5e-4;
  double prev = t0;
  if (s.insideOutside(o + t0 * d) < 1.0) return t0;
  for (double t = t0 + kStep; t <= t1 + kStep; t += kStep) {
    const double tt = std::min(t, t1);
    if (s.insideOutside(o + tt * d) < 1.0) {
      double lo = prev, hi = tt;
      for (int i = 0; i < 40; ++i) {
        const double mid = 0.5 * (lo + hi);
        (s.insideOutside(o + mid * d) < 1.0 ? hi : lo) = mid;
      }
      return hi;
    }
    prev = tt;
    if (tt >= t1) break;
  }
  return std::nullopt;
}

}  // namespace

StriperRenderer::StriperRenderer(const ProceduralTerrain& terrain, RayCasterOptions options)
    : ground_(withoutRocks(terrain.description(), ground_features_)), caster_(ground_, options) {
  const auto& features = terrain.description().features;
  for (std::size_t i = 0; i < features.size(); ++i)
    if (const auto* rock = std::get_if<Rock>(&features[i]))
      rocks_.emplace_back(int(i), rock->shape);
}

std::optional<StriperRenderer::Hit> StriperRenderer::firstHit(const Eigen::Vector3d& origin,
                                                              const Eigen::Vector3d& direction,
                                                              double max_range) const {
  std::optional<Hit> best;
  if (const auto t = caster_.cast(origin, direction, max_range)) {
    const Eigen::Vector3d p = origin + *t * direction;
    const int f = ground_.featureAt(p.x(), p.y());
    best = Hit{*t, f < 0 ? -1 : ground_features_[std::size_t(f)]};
  }
  for (const auto& [index, shape] : rocks_)
    if (const auto t = enterSuperquadric(shape, origin, direction, best ? best->t : max_range))
      if (!best || *t < best->t) best = Hit{*t, index};
  return best;
}

Eigen::Vector3d StriperRenderer::normalAt(const Eigen::Vector3d& p, int feature) const {
  for (const auto& [index, shape] : rocks_) {
    if (index != feature) continue;
    const double h = 1e-4;
    Eigen::Vector3d g;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e[k] = h;
      g[k] = shape.insideOutside(p + e) - shape.insideOutside(p - e);
    }
    return g.normalized();
  }
  return surfaceNormal(ground_, p.x(), p.y());
}

StriperScene StriperRenderer::render(const StriperModel& model, std::uint64_t noise_seed) const {
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
      const auto hit = firstHit(eye, dir, reach);
      if (!hit) continue;
      const Eigen::Vector3d p = eye + hit->t * dir;
      scene.labels(r, c) =
          hit->feature < 0 ? kLabelGround : static_cast<unsigned char>(hit->feature + 1);
      const auto i = img.index(r, c);

      const Eigen::Vector3d to_projector = model.projector_position - p;
      const double light_distance = to_projector.norm();
      const auto blocker =
          firstHit(model.projector_position, -to_projector / light_distance, light_distance + 1.0);
      const bool lit = !blocker || blocker->t > light_distance - 2e-3;
      const double shade =
          std::max(0.0, normalAt(p, hit->feature).dot(to_projector) / light_distance);
      img.intensity[i] = float(albedo(hit->feature) * (0.05 + (lit ? 0.95 * shade : 0.0)));
      if (!lit) continue;  // range shadow: the striper measures nothing here
      const Eigen::Vector3d measured = eye + (hit->t + model.noise_sigma * unit_normal(rng)) * dir;
      img.x[i] = float(measured.x());
      img.y[i] = float(measured.y());
      img.z[i] = float(measured.z());
    }
  }
  return scene;
}

StriperScene simulateStriper(const ProceduralTerrain& terrain, const StriperModel& model,
                             std::uint64_t noise_seed) {
  return StriperRenderer(terrain, {.cell_size = 0.02, .step = 0.001}).render(model, noise_seed);
}

}  // namespace ambler::sim
