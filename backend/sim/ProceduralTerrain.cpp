#include "sim/ProceduralTerrain.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ambler::sim {

namespace {

constexpr double kNoTop = -std::numeric_limits<double>::infinity();

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};

const Footprint* footprintOf(const Feature& f) {
  return std::visit(Overloaded{[](const Rock&) -> const Footprint* { return nullptr; },
                               [](const auto& other) { return &other.footprint; }},
                    f);
}

}  // namespace

Eigen::Vector2d Footprint::toLocal(double x, double y) const {
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double dx = x - cx, dy = y - cy;
  return {c * dx + s * dy, -s * dx + c * dy};
}

bool Footprint::contains(double x, double y) const {
  const auto p = toLocal(x, y);
  return std::abs(p.x()) <= half_x && std::abs(p.y()) <= half_y;
}

Box2 Footprint::bounds() const {
  const double c = std::abs(std::cos(yaw)), s = std::abs(std::sin(yaw));
  const double ex = c * half_x + s * half_y, ey = s * half_x + c * half_y;
  return {cx - ex, cy - ey, cx + ex, cy + ey};
}

ProceduralTerrain::ProceduralTerrain(TerrainDescription description)
    : description_(std::move(description)) {
  for (const auto& w : description_.waves)
    wave_slope_bound_ += std::abs(w.amplitude) * std::hypot(w.kx, w.ky);

  for (const auto& f : description_.features) {
    if (const auto* fp = footprintOf(f)) {
      const double ground = groundHeight(fp->cx, fp->cy);
      feature_bounds_.push_back(fp->bounds());
      feature_top_.push_back(std::visit(
          Overloaded{[&](const BoxObstacle& b) { return ground + b.height; },
                     [&](const Trench&) { return kNoTop; },
                     [&](const Ramp& r) {
                       const auto foot = r.footprint;
                       const double c = std::cos(foot.yaw), s = std::sin(foot.yaw);
                       return groundHeight(foot.cx - c * foot.half_x, foot.cy - s * foot.half_x) +
                              r.height;
                     },
                     [](const Rock&) { return 0.0; }},
          f));
    } else {
      const auto& rock = std::get<Rock>(f).shape;
      const double r = rock.footprintRadius();
      const auto c = rock.pose.translation();
      feature_bounds_.push_back({c.x() - r, c.y() - r, c.x() + r, c.y() + r});
      feature_top_.push_back(c.z() + rock.size.z());
    }
  }

  const auto& e = description_.extent;
  bin_cols_ = std::max(1, int(std::ceil(e.width() / bin_size_)));
  bin_rows_ = std::max(1, int(std::ceil(e.height() / bin_size_)));
  bins_.assign(std::size_t(bin_cols_) * bin_rows_, {});
  for (int i = 0; i < int(feature_bounds_.size()); ++i) {
    const auto& b = feature_bounds_[std::size_t(i)];
    const int c0 = std::clamp(int((b.x_min - e.x_min) / bin_size_), 0, bin_cols_ - 1);
    const int c1 = std::clamp(int((b.x_max - e.x_min) / bin_size_), 0, bin_cols_ - 1);
    const int r0 = std::clamp(int((b.y_min - e.y_min) / bin_size_), 0, bin_rows_ - 1);
    const int r1 = std::clamp(int((b.y_max - e.y_min) / bin_size_), 0, bin_rows_ - 1);
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c) bins_[std::size_t(r) * bin_cols_ + c].push_back(i);
  }
}

double ProceduralTerrain::groundHeight(double x, double y) const {
  double z = description_.base_height;
  for (const auto& w : description_.waves)
    z += w.amplitude * std::sin(w.kx * x + w.ky * y + w.phase);
  return z;
}

const std::vector<int>& ProceduralTerrain::featuresNear(double x, double y) const {
  const auto& e = description_.extent;
  const int c = int((x - e.x_min) / bin_size_), r = int((y - e.y_min) / bin_size_);
  if (c < 0 || r < 0 || c >= bin_cols_ || r >= bin_rows_) return no_features_;
  return bins_[std::size_t(r) * bin_cols_ + c];
}

ProceduralTerrain::Evaluated ProceduralTerrain::evaluate(double x, double y) const {
  Evaluated out{groundHeight(x, y), -1};
  const auto& near = featuresNear(x, y);
  // Trenches carve the ground first; raised features then sit on the result.
  for (int i : near) {
    const auto& f = description_.features[std::size_t(i)];
    if (const auto* t = std::get_if<Trench>(&f); t && t->footprint.contains(x, y)) {
      out = {groundHeight(t->footprint.cx, t->footprint.cy) - t->depth, i};
    }
  }
  for (int i : near) {
    const auto& f = description_.features[std::size_t(i)];
    const double top = std::visit(
        Overloaded{[&](const BoxObstacle& b) {
                     return b.footprint.contains(x, y) ? feature_top_[std::size_t(i)] : kNoTop;
                   },
                   [](const Trench&) { return kNoTop; },
                   [&](const Ramp& r) {
                     if (!r.footprint.contains(x, y)) return kNoTop;
                     const double u = r.footprint.toLocal(x, y).x() + r.footprint.half_x;
                     const double rise = u < r.run ? r.height * u / r.run : r.height;
                     return feature_top_[std::size_t(i)] - r.height + rise;
                   },
                   [&](const Rock& rock) { return rock.shape.topHeight(x, y).value_or(kNoTop); }},
        f);
    if (top > out.z) out = {top, i};
  }
  return out;
}

double ProceduralTerrain::height(double x, double y) const {
  if (!description_.extent.contains(x, y)) return std::numeric_limits<double>::quiet_NaN();
  return evaluate(x, y).z;
}

int ProceduralTerrain::featureAt(double x, double y) const { return evaluate(x, y).feature; }

double ProceduralTerrain::maxHeightIn(const Box2& box) const {
  const double cx = 0.5 * (box.x_min + box.x_max), cy = 0.5 * (box.y_min + box.y_max);
  const double half_diagonal = 0.5 * std::hypot(box.width(), box.height());
  double bound = groundHeight(cx, cy) + wave_slope_bound_ * half_diagonal;
  for (std::size_t i = 0; i < feature_bounds_.size(); ++i) {
    const auto& b = feature_bounds_[i];
    const bool overlaps = b.x_min <= box.x_max && b.x_max >= box.x_min && b.y_min <= box.y_max &&
                          b.y_max >= box.y_min;
    if (overlaps) bound = std::max(bound, feature_top_[i]);
  }
  return bound;
}

}  // namespace ambler::sim
