#include "vision/RoughRoute.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace ambler::vision {

namespace {

// The danger image seen with rows from the bottom, and the route corridor's
// half width per row.
class RouteGround {
 public:
  RouteGround(const io::FloatImage& danger, const CameraModel& camera, double threshold)
      : danger_(danger), threshold_(threshold), half_(std::size_t(danger.rows), 1) {
    // The shade window (the rover's diagonal on the ground) ending at or
    // above each row; 3 pixels beyond the last one wider than 2.
    int y = 0;
    for (int k = 0; y < danger.rows; ++k) {
      const double width = windowWidth(camera, k, camera.rover_diagonal_m);
      const double end = rowAt(camera, windowAngle(camera, k, camera.rover_diagonal_m));
      if (width <= 2) break;
      for (; y < std::min(double(danger.rows), end); ++y) half_[std::size_t(y)] = int(width / 2);
    }
    for (; y < danger.rows; ++y) half_[std::size_t(y)] = 1;
  }
  int rows() const { return danger_.rows; }
  int cols() const { return danger_.cols; }
  int half(double y) const { return half_[std::size_t(std::clamp(int(y), 0, rows() - 1))]; }
  double at(int x, int y) const { return danger_(rows() - 1 - y, x); }
  // Off the image, sky, or above the threshold.
  bool blocked(int x, int y) const {
    if (x < 0 || y < 0 || x >= cols() || y >= rows()) return true;
    const double d = at(x, y);
    return !(d <= threshold_);
  }
  // The corridor across row y centred on x is free.
  bool clear(double x, double y) const {
    const int xi = int(std::lround(x)), yi = int(std::lround(y)), h = half(y);
    for (int c = xi - h; c <= xi + h; ++c)
      if (blocked(c, yi)) return false;
    return true;
  }
  double meanAcross(double x, double y) const {
    const int xi = int(std::lround(x)), yi = int(std::lround(y)), h = half(y);
    double sum = 0;
    int n = 0;
    for (int c = std::max(xi - h, 0); c <= std::min(xi + h, cols() - 1); ++c)
      if (std::isfinite(at(c, yi))) sum += at(c, yi), ++n;
    return n ? sum / n : 1.0;
  }

 private:
  const io::FloatImage& danger_;
  double threshold_;
  std::vector<int> half_;
};

// The points of a -> b, one per pixel of its longer extent.
std::vector<ImagePoint> samples(const ImagePoint& a, const ImagePoint& b) {
  const int n = std::max(1, int(std::ceil(std::max(std::abs(b.y - a.y), std::abs(b.x - a.x)))));
  std::vector<ImagePoint> out;
  for (int i = 0; i <= n; ++i) {
    const double s = double(i) / n;
    out.push_back({a.x + s * (b.x - a.x), a.y + s * (b.y - a.y)});
  }
  return out;
}

// The nearest free corridor centre on row y, sideways from x.
std::optional<double> sideways(const RouteGround& g, double x, double y, int direction) {
  for (int s = 1; s < g.cols(); ++s) {
    const double c = x + direction * s;
    if (c < 0 || c >= g.cols()) return std::nullopt;
    if (g.clear(c, y)) return c;
  }
  return std::nullopt;
}

// §4.1: where a -> b is first blocked, the stretch of blocked points; on
// each side, the point the rover must leave the straight route most to
// pass. The Way Area is that point on the side that leaves it less (if
// even, the less dangerous side).
std::optional<ImagePoint> wayArea(const RouteGround& g, const std::vector<ImagePoint>& leg,
                                  std::size_t first) {
  struct Side {
    double worst = -1;  // the largest departure [pixel]
    ImagePoint at{};
    bool possible = true;
  } left, right;
  for (std::size_t i = first; i < leg.size() && !g.clear(leg[i].x, leg[i].y); ++i) {
    const ImagePoint& p = leg[i];
    for (auto [side, direction] : {std::pair{&left, -1}, std::pair{&right, +1}}) {
      if (!side->possible) continue;
      const auto x = sideways(g, p.x, p.y, direction);
      if (!x) {
        side->possible = false;
        continue;
      }
      if (std::abs(*x - p.x) > side->worst) side->worst = std::abs(*x - p.x), side->at = {*x, p.y};
    }
  }
  if (!left.possible && !right.possible) return std::nullopt;
  if (!left.possible) return right.at;
  if (!right.possible) return left.at;
  if (right.worst < left.worst) return right.at;
  if (left.worst < right.worst) return left.at;
  return g.meanAcross(right.at.x, right.at.y) < g.meanAcross(left.at.x, left.at.y) ? right.at
                                                                                   : left.at;
}

bool plan(const RouteGround& g, const ImagePoint& a, const ImagePoint& b, int& budget,
          std::vector<ImagePoint>& way) {
  const auto leg = samples(a, b);
  std::size_t first = 0;
  while (first < leg.size() && g.clear(leg[first].x, leg[first].y)) ++first;
  if (first == leg.size()) return true;
  if (budget-- <= 0) return false;
  const auto wa = wayArea(g, leg, first);
  if (!wa) return false;
  if (!plan(g, a, *wa, budget, way)) return false;
  way.push_back(*wa);
  return plan(g, *wa, b, budget, way);
}

// Moves p sideways to the nearest free corridor on its row.
bool moveOutOfDanger(const RouteGround& g, ImagePoint& p) {
  if (g.clear(p.x, p.y)) return false;
  const auto left = sideways(g, p.x, p.y, -1), right = sideways(g, p.x, p.y, +1);
  if (left && (!right || p.x - *left <= *right - p.x))
    p.x = *left;
  else if (right)
    p.x = *right;
  return true;
}

}  // namespace

RoughRoute planRoughRoute(const io::FloatImage& danger, const CameraModel& camera,
                          const ImagePoint* goal, const RouteOptions& o) {
  validate(camera);
  if (danger.rows != camera.rows)
    throw std::invalid_argument("route: the danger image's rows are not the camera's");
  if (!(o.threshold_share > 0 && o.threshold_share < 1))
    throw std::invalid_argument("route: threshold_share must be in (0, 1)");
  RoughRoute r;
  double sum = 0;
  int n = 0;
  for (const float d : danger.pixels)
    if (std::isfinite(d)) sum += d, ++n;
  if (n == 0) return r.reason = "the image shows no ground", r;
  const double mean = sum / n;
  r.threshold = mean + o.threshold_share * (1 - mean);
  const RouteGround g(danger, camera, r.threshold);
  const Bands bands = bandsOf(camera);
  // Start Area: the square of the second shade window at the bottom centre.
  const double side = windowWidth(camera, 1, camera.rover_diagonal_m);
  r.start = {0.5 * (danger.cols - 1), std::min(0.5 * side, bands.y_h - 1.0)};
  r.destination = goal ? *goal : ImagePoint{0.5 * (danger.cols - 1), bands.y_h - 3.0};
  if (r.destination.y < 0 || r.destination.y >= bands.y_h || r.destination.x < 0 ||
      r.destination.x >= danger.cols)
    return r.reason = "the goal is not on the ground in the image", r;
  r.start_moved = moveOutOfDanger(g, r.start);
  r.destination_moved = moveOutOfDanger(g, r.destination);
  if (!g.clear(r.start.x, r.start.y)) return r.reason = "no safe start area on the bottom row", r;
  if (!g.clear(r.destination.x, r.destination.y))
    return r.reason = "no safe destination area on the goal's row", r;
  int budget = o.max_way_areas;
  if (!plan(g, r.start, r.destination, budget, r.way_areas))
    return r.reason = "no route within " + std::to_string(o.max_way_areas) + " way areas", r;
  r.found = true;
  r.route.push_back(r.start);
  r.route.insert(r.route.end(), r.way_areas.begin(), r.way_areas.end());
  r.route.push_back(r.destination);
  return r;
}

const char* toString(SafeRate rate) {
  switch (rate) {
    case SafeRate::kSafe:
      return "safe";
    case SafeRate::kALittleSafe:
      return "a little safe";
    case SafeRate::kALittleAttention:
      return "a little attention";
    case SafeRate::kAttention:
      return "attention";
    case SafeRate::kSpecialAttention:
      return "special attention";
  }
  return "?";
}

const char* describe(SensingAction action) {
  switch (action) {
    case SensingAction::kA:
      return "A: move without sensing";
    case SensingAction::kB:
      return "B: grey-level images on the way, confirm the safety in front";
    case SensingAction::kC:
      return "C: range to the dangerous areas (LRF or stereo) on the way";
    case SensingAction::kD:
      return "D: detailed map (LRF or stereo), avoid the dangerous areas exactly";
    case SensingAction::kE:
      return "E: recognize and plan again from a new image, on the route";
    case SensingAction::kF:
      return "F: turn to the destination, recognize and plan from a new image";
  }
  return "?";
}

std::vector<SensingStep> planSensing(const io::FloatImage& danger, const CameraModel& camera,
                                     const RoughRoute& route) {
  std::vector<SensingStep> steps;
  if (!route.found) return steps;
  const Bands bands = bandsOf(camera);
  const RouteGround g(danger, camera, route.threshold);
  steps.push_back({"start", route.start, route.start, SafeRate::kSafe, SensingAction::kF});
  // Clearance of a route point: the nearest dangerous pixel across its row,
  // in corridor widths.
  auto rate = [&](const ImagePoint& p) {
    const int y = int(std::lround(p.y)), x = int(std::lround(p.x)), h = std::max(g.half(p.y), 1);
    int gap = 4 * 2 * h;
    auto dangerous = [&](int c) { return c >= 0 && c < g.cols() && g.blocked(c, y); };
    for (int s = 0; s < gap; ++s)
      if (dangerous(x - s) || dangerous(x + s)) gap = s;
    const double widths = double(gap) / (2 * h);
    return widths >= 3     ? SafeRate::kSafe
           : widths >= 2   ? SafeRate::kALittleSafe
           : widths >= 1   ? SafeRate::kALittleAttention
           : widths >= 0.5 ? SafeRate::kAttention
                           : SafeRate::kSpecialAttention;
  };
  auto action = [](bool shortBand, SafeRate r) {
    switch (r) {
      case SafeRate::kSafe:
        return SensingAction::kA;
      case SafeRate::kALittleSafe:
        return SensingAction::kB;
      case SafeRate::kALittleAttention:
        return shortBand ? SensingAction::kB : SensingAction::kC;
      case SafeRate::kAttention:
        return SensingAction::kC;
      case SafeRate::kSpecialAttention:
        return SensingAction::kD;
    }
    return SensingAction::kD;
  };
  for (std::size_t leg = 0; leg + 1 < route.route.size(); ++leg)
    for (const auto& p : samples(route.route[leg], route.route[leg + 1])) {
      const std::string band = p.y < bands.y_v ? "short" : p.y < bands.y_g ? "middle" : "long";
      if (band == "long") {
        if (steps.back().band != "long")
          steps.push_back({"long", p, route.destination, SafeRate::kSafe, SensingAction::kE});
        continue;
      }
      const SafeRate r = rate(p);
      const SensingAction act = action(band == "short", r);
      if (steps.back().band == band && steps.back().rate == r)
        steps.back().to = p;
      else
        steps.push_back({band, p, p, r, act});
    }
  return steps;
}

}  // namespace ambler::vision
