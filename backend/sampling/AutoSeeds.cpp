#include "sampling/AutoSeeds.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <stdexcept>
#include <string>

namespace ambler::sampling {

namespace {

// Where the projector appears in the image; for a projector behind the
// camera the direction towards it is reversed, which `towards` handles.
struct Epipole {
  Eigen::Vector2d pixel;
  bool in_front;
};

Epipole projectorInImage(const sensor::StriperImage& image) {
  return {image.camera.pixelOf(image.projector_position),
          image.camera.inFront(image.projector_position)};
}

Eigen::Vector2d towards(const Epipole& e, const Eigen::Vector2d& from) {
  const Eigen::Vector2d d = (e.pixel - from).normalized();
  return e.in_front ? d : -d;
}

// From A towards the light: past the rim's feature pixels, then the
// nominal radius further, or halfway to the far rim if that comes first.
std::optional<Eigen::Vector2d> seedBeyond(const FeatureMap& f, const Eigen::Vector2d& a,
                                          const Eigen::Vector2d& light, double radius) {
  auto feature = [&](double d) {
    const Eigen::Vector2d q = a + d * light;
    return f.isFeature(int(std::lround(q.y())), int(std::lround(q.x())));
  };
  double inside = 1.0;
  while (inside <= radius && feature(inside)) inside += 1.0;
  if (inside > radius) return std::nullopt;  // no way in
  double far = inside;
  while (far - inside < 2 * radius && !feature(far + 1.0)) far += 1.0;
  return a + std::min(inside + radius, 0.5 * (inside + far)) * light;
}

}  // namespace

void validate(const SeedOptions& o) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("seed option " + what);
  };
  require(o.radius_px > 0 && o.radius_px <= 500, "radius_px must be in (0, 500]");
  require(o.min_width_px >= 0 && o.min_width_px < o.max_width_px,
          "min_width_px must be >= 0 and below max_width_px");
  require(o.min_shadow_px >= 1, "min_shadow_px must be >= 1");
}

double pixelsPerMetre(const sensor::PinholeCamera& camera, const Eigen::Vector3d& at) {
  const double depth = (camera.camera_to_world.inverse() * at).z();
  return depth > 0 ? camera.fx / depth : 0.0;
}

std::vector<Seed> automaticSeeds(const sensor::StriperImage& image, const FeatureMap& features,
                                 const SeedOptions& o) {
  validate(o);
  cv::Mat shadow(features.rows, features.cols, CV_8U, cv::Scalar(0));
  for (int r = 0; r < features.rows; ++r)
    for (int c = 0; c < features.cols; ++c)
      if (features.kindAt(r, c) & kShadow) shadow.at<std::uint8_t>(r, c) = 255;
  cv::Mat labels;
  const int n = cv::connectedComponents(shadow, labels, 8, CV_32S);
  std::vector<std::vector<Eigen::Vector2d>> regions(std::size_t(std::max(n - 1, 0)));
  std::vector<bool> on_border(regions.size(), false);
  for (int r = 0; r < features.rows; ++r)
    for (int c = 0; c < features.cols; ++c)
      if (const int l = labels.at<int>(r, c); l > 0) {
        regions[std::size_t(l - 1)].push_back({double(c), double(r)});
        if (r == 0 || c == 0 || r + 1 == features.rows || c + 1 == features.cols)
          on_border[std::size_t(l - 1)] = true;
      }
  const Epipole epipole = projectorInImage(image);
  std::vector<Seed> seeds;
  for (std::size_t k = 0; k < regions.size(); ++k) {
    const auto& px = regions[k];
    if (on_border[k] || int(px.size()) < o.min_shadow_px) continue;
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (const auto& p : px) centroid += p / double(px.size());
    const Eigen::Vector2d light = towards(epipole, centroid);  // towards the projector
    const Eigen::Vector2d across(-light.y(), light.x());
    // On the light ray through the shadow's middle (a crescent's tips
    // would mislead elsewhere), the shadow's end next to the occluder: A.
    double near = -INFINITY, lo = INFINITY, hi = -INFINITY;
    for (const auto& p : px) {
      const double along = (p - centroid).dot(light), side = (p - centroid).dot(across);
      if (std::abs(side) <= 1.5) near = std::max(near, along);
      lo = std::min(lo, side), hi = std::max(hi, side);
    }
    const double width = hi - lo + 1;
    if (width < o.min_width_px || width > o.max_width_px || !std::isfinite(near)) continue;
    const Eigen::Vector2d a = centroid + near * light;
    if (const auto s = seedBeyond(features, a, light, o.radius_px))
      seeds.push_back({*s, int(k), width});
  }
  return seeds;
}

}  // namespace ambler::sampling
