#include "sim/CameraRender.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/Angles.h"

namespace ambler::sim {

namespace {

// The surface normal from central differences of the height.
Eigen::Vector3d normalAt(const Terrain& t, double x, double y) {
  const double h = 0.02;
  const double dx = (t.height(x + h, y) - t.height(x - h, y)) / (2 * h);
  const double dy = (t.height(x, y + h) - t.height(x, y - h)) / (2 * h);
  if (!std::isfinite(dx) || !std::isfinite(dy)) return Eigen::Vector3d::UnitZ();
  return Eigen::Vector3d(-dx, -dy, 1).normalized();
}

}  // namespace

RenderedImage renderCamera(const ProceduralTerrain& terrain, const RayCaster& caster,
                           const CameraShot& s, double rough_height_m) {
  RenderedImage out{io::FloatImage(s.rows, s.cols, 0.0f), io::ByteImage(s.rows, s.cols, 255)};
  const Eigen::Vector3d ahead(-std::sin(s.heading), std::cos(s.heading), 0);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ(), right(ahead.y(), -ahead.x(), 0);
  const double a = s.alpha_deg * kDeg;
  const Eigen::Vector3d axis = std::sin(a) * ahead - std::cos(a) * up;
  const Eigen::Vector3d image_up = std::cos(a) * ahead + std::sin(a) * up;
  const double f = 0.5 * s.rows / std::tan(0.5 * s.beta_deg * kDeg);
  const double ground = terrain.height(s.ground_xy.x(), s.ground_xy.y());
  const Eigen::Vector3d eye(s.ground_xy.x(), s.ground_xy.y(),
                            (std::isfinite(ground) ? ground : 0.0) + s.height_m);
  const double sun_az = s.heading + s.sun_azimuth_deg * kDeg, sun_el = s.sun_elevation_deg * kDeg;
  const Eigen::Vector3d sun(-std::sin(sun_az) * std::cos(sun_el),
                            std::cos(sun_az) * std::cos(sun_el), std::sin(sun_el));
  constexpr double kAmbient = 0.12, kMaxRange = 200.0;
#pragma omp parallel for schedule(dynamic, 4)
  for (int r = 0; r < s.rows; ++r) {
    std::mt19937 grain(std::uint32_t(s.texture_seed * 1000003u + std::uint64_t(r)));
    std::normal_distribution<double> noise(0.0, 1.0);
    for (int c = 0; c < s.cols; ++c) {
      const Eigen::Vector3d ray =
          (f * axis + (c + 0.5 - 0.5 * s.cols) * right + (0.5 * s.rows - (r + 0.5)) * image_up)
              .normalized();
      const auto t = caster.cast(eye, ray, kMaxRange);
      const double n1 = noise(grain);
      if (!t) {
        // Below the horizon but past the course's edge: far, flat sand.
        if (ray.z() < 0)
          out.rough(r, c) = 0, out.grey(r, c) =
                                   float(std::clamp(255.0 * 0.85 * (1 + 0.02 * n1) *
                                                        (kAmbient + (1 - kAmbient) * sun.z()) * 1.6,
                                                    0.0, 255.0));
        continue;  // else sky: black
      }
      const Eigen::Vector3d p = eye + *t * ray;
      const bool feature = terrain.featureAt(p.x(), p.y()) >= 0;
      const bool rough =
          feature && std::abs(p.z() - terrain.groundHeight(p.x(), p.y())) > rough_height_m;
      out.rough(r, c) = rough ? 1 : 0;
      const bool lit = !caster.cast(p + 0.01 * up, sun, kMaxRange);
      const double light =
          kAmbient +
          (1 - kAmbient) * (lit ? std::max(0.0, normalAt(terrain, p.x(), p.y()).dot(sun)) : 0.0);
      // Sand: albedo 0.85 with a 2 % grain; features 0.45 with 25 %.
      const double albedo = feature ? 0.45 * (1 + 0.25 * n1) : 0.85 * (1 + 0.02 * n1);
      out.grey(r, c) = float(std::clamp(255.0 * albedo * light * 1.6, 0.0, 255.0));
    }
  }
  return out;
}

}  // namespace ambler::sim
