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

bool overlap(const Box2& a, const Box2& b) {
  return a.x_min <= b.x_max && a.x_max >= b.x_min && a.y_min <= b.y_max && a.y_max >= b.y_min;
}

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

double Crater::relief(double x, double y) const {
  const double R = radius();
  const double r = std::hypot(x - cx, y - cy);
  if (r <= R) {
    const double floor = rim_height - depth;
    return floor + (rim_height - floor) * (r / R) * (r / R);
  }
  if (r >= 3 * R) return 0.0;
  // Ejecta, shifted so that it meets the plain ground at 3 R.
  const double q = R / r;
  return rim_height * (q * q * q - 1.0 / 27) / (1 - 1.0 / 27);
}

std::array<int, 4> ProceduralTerrain::Bins::range(const Box2& b) const {
  auto col = [&](double x) { return std::clamp(int((x - extent.x_min) / size), 0, cols - 1); };
  auto row = [&](double y) { return std::clamp(int((y - extent.y_min) / size), 0, rows - 1); };
  return {col(b.x_min), col(b.x_max), row(b.y_min), row(b.y_max)};
}

template <class F>
void ProceduralTerrain::Bins::forEachIn(const Box2& box, F&& f) const {
  const auto [c0, c1, r0, r1] = range(box);
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c)
      for (int i : items[std::size_t(r) * cols + c]) f(i);
}

void ProceduralTerrain::Bins::build(const Box2& e, const std::vector<Box2>& bounds) {
  extent = e;
  cols = std::max(1, int(std::ceil(e.width() / size)));
  rows = std::max(1, int(std::ceil(e.height() / size)));
  items.assign(std::size_t(cols) * rows, {});
  for (int i = 0; i < int(bounds.size()); ++i) {
    const auto [c0, c1, r0, r1] = range(bounds[std::size_t(i)]);
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c) items[std::size_t(r) * cols + c].push_back(i);
  }
}

const std::vector<int>& ProceduralTerrain::Bins::near(double x, double y) const {
  static const std::vector<int> kNone;
  const int c = int(std::floor((x - extent.x_min) / size));
  const int r = int(std::floor((y - extent.y_min) / size));
  if (c < 0 || r < 0 || c >= cols || r >= rows) return kNone;
  return items[std::size_t(r) * cols + c];
}

ProceduralTerrain::ProceduralTerrain(TerrainDescription description)
    : description_(std::move(description)), wave_sum_(description_.waves) {
  std::vector<Box2> crater_bounds;
  for (const auto& c : description_.craters)
    crater_bounds.push_back(
        {c.cx - c.reach(), c.cy - c.reach(), c.cx + c.reach(), c.cy + c.reach()});
  crater_bins_.build(description_.extent, crater_bounds);

  for (const auto& f : description_.features) {
    if (const auto* fp = footprintOf(f)) {
      const double ground = groundHeight(fp->cx, fp->cy);
      feature_bounds_.push_back(fp->bounds());
      feature_top_.push_back(std::visit(
          Overloaded{[&](const BoxObstacle& b) { return ground + b.height; },
                     // The rim: a trench's walls fall from there to its floor.
                     [&](const Trench&) { return ground; },
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
  // Finer bins where features are dense (rock fields), so that a height
  // looks at few of them.
  const double per_m2 = double(feature_bounds_.size()) /
                        std::max(1.0, description_.extent.width() * description_.extent.height());
  feature_bins_.size = per_m2 > 1.0 ? 0.5 : 2.0;
  feature_bins_.build(description_.extent, feature_bounds_);
}

double ProceduralTerrain::planeAndWaves(double x, double y) const {
  return description_.base_height + description_.gradient.dot(Eigen::Vector2d(x, y)) +
         wave_sum_(x, y);
}

double ProceduralTerrain::groundHeight(double x, double y) const {
  double z = planeAndWaves(x, y);
  for (int i : crater_bins_.near(x, y)) z += description_.craters[std::size_t(i)].relief(x, y);
  return z;
}

namespace {

double trenchHeight(const Trench& t, double rim, double x, double y) {
  const double floor = rim - t.depth;
  if (t.wall_run <= 0.0) return floor;
  const double from_edge = t.footprint.half_y - std::abs(t.footprint.toLocal(x, y).y());
  return from_edge >= t.wall_run ? floor : rim - t.depth * from_edge / t.wall_run;
}

}  // namespace

ProceduralTerrain::Evaluated ProceduralTerrain::evaluate(double x, double y) const {
  Evaluated out{groundHeight(x, y), -1};
  const auto& near = feature_bins_.near(x, y);
  // Trenches carve the ground first; raised features then sit on the result.
  for (int i : near) {
    const auto& f = description_.features[std::size_t(i)];
    if (const auto* t = std::get_if<Trench>(&f); t && t->footprint.contains(x, y))
      out = {trenchHeight(*t, feature_top_[std::size_t(i)], x, y), i};
  }
  for (int i : near) {
    if (!feature_bounds_[std::size_t(i)].contains(x, y)) continue;
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
  const double r = 0.5 * std::hypot(box.width(), box.height());
  // Each wave stays within its amplitude and within its slope times the
  // distance from the centre: the first bounds the short waves, the second
  // the long ones.
  double bound = description_.base_height + description_.gradient.dot(Eigen::Vector2d(cx, cy)) +
                 description_.gradient.norm() * r;
  for (const auto& w : description_.waves) {
    const double a = std::abs(w.amplitude);
    const double at_centre = w.amplitude * std::sin(w.kx * cx + w.ky * cy + w.phase);
    bound += std::min(a, at_centre + a * std::hypot(w.kx, w.ky) * r);
  }
  // Craters add to each other where they overlap; each adds at most its rim.
  std::vector<int> craters;
  crater_bins_.forEachIn(box, [&](int i) { craters.push_back(i); });
  std::sort(craters.begin(), craters.end());
  craters.erase(std::unique(craters.begin(), craters.end()), craters.end());
  for (int i : craters) bound += std::max(0.0, description_.craters[std::size_t(i)].rim_height);
  feature_bins_.forEachIn(box, [&](int i) {
    if (overlap(feature_bounds_[std::size_t(i)], box))
      bound = std::max(bound, feature_top_[std::size_t(i)]);
  });
  return bound;
}

}  // namespace ambler::sim
