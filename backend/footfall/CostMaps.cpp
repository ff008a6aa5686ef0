#include "footfall/CostMaps.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "footfall/Footprint.h"

namespace ambler::footfall {

namespace {

void requireRange(bool ok, const char* field, const char* range) {
  if (!ok)
    throw std::invalid_argument(std::string("cost map option ") + field + " must be " + range);
}

// Share of the segment a-b inside the wedge at `apex` of half-angle
// `half` <= 90 deg about `axis`: the intersection of two half-planes, each
// a linear bound on the segment's parameter.
double shareInWedge(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& apex,
                    double axis, double half) {
  const Eigen::Vector2d inward[] = {{std::sin(axis + half), -std::cos(axis + half)},
                                    {-std::sin(axis - half), std::cos(axis - half)}};
  double lo = 0.0, hi = 1.0;
  for (const auto& n : inward) {
    const double f0 = n.dot(a - apex), f1 = n.dot(b - a);  // f0 + t f1 >= 0
    if (f1 > 0)
      lo = std::max(lo, -f0 / f1);
    else if (f1 < 0)
      hi = std::min(hi, -f0 / f1);
    else if (f0 < 0)
      return 0.0;
  }
  return std::max(hi - lo, 0.0);
}

}  // namespace

void validate(const CostMapOptions& o) {
  validate(o.foot);
  const auto& l = o.limits;
  requireRange(l.reach_min_m >= 0 && l.reach_max_m > l.reach_min_m && l.reach_max_m <= 50,
               "limits.reach_min_m/reach_max_m", "0 <= min < max <= 50 m");
  requireRange(l.elevation_max_m > l.elevation_min_m && std::isfinite(l.elevation_min_m) &&
                   std::isfinite(l.elevation_max_m),
               "limits.elevation_min_m/elevation_max_m", "finite with min < max");
  const auto& w = o.weights;
  for (const double v : {w.roughness, w.slope, w.body_advance, w.visibility})
    requireRange(v >= 0 && v <= 1000, "weights", "in [0, 1000]");
  requireRange(o.roughness_scale > 0 && std::isfinite(o.roughness_scale), "roughness_scale",
               "a positive number");
  requireRange(o.max_body_advance_m > 0 && o.max_body_advance_m <= 50, "max_body_advance_m",
               "in (0, 50] m");
}

double bodyAdvance(const Eigen::Vector2d& foot, const LegContext& leg, double reach_max,
                   double max_advance) {
  return bodyAdvance(foot, leg.shaft, {std::cos(leg.heading_rad), std::sin(leg.heading_rad)},
                     reach_max, max_advance);
}

double bodyAdvance(const Eigen::Vector2d& foot, const Eigen::Vector2d& shaft,
                   const Eigen::Vector2d& h, double reach_max, double max_advance) {
  const Eigen::Vector2d q = foot - shaft;
  const double along = q.dot(h), across2 = q.squaredNorm() - along * along;
  if (across2 > reach_max * reach_max) return 0.0;
  // The shaft moves to shaft + d h; the foot stays within reach while
  // |q - d h| <= reach_max.
  return std::clamp(along + std::sqrt(reach_max * reach_max - across2), 0.0, max_advance);
}

double linkInView(const Eigen::Vector2d& foot, const Eigen::Vector2d& shaft,
                  const ScannerView& scanner) {
  const double half = scanner.horizontal_fov_rad / 2;
  // A view wider than 180 degrees is the complement of a narrow wedge.
  if (half > M_PI / 2)
    return 1.0 -
           shareInWedge(foot, shaft, scanner.position, scanner.heading_rad + M_PI, M_PI - half);
  return shareInWedge(foot, shaft, scanner.position, scanner.heading_rad, half);
}

CostMaps buildCostMaps(const terrain::ElevationMap& map, const Box2& region, const LegContext& leg,
                       const CostMapOptions& o) {
  validate(o);
  const auto stats =
      footprintStatistics(map, region, o.foot, o.roughness_criterion == Criterion::kSupportArea);
  const ScoreMap criterion = scoreMapOf(stats, o.roughness_criterion, o.foot);
  const ScoreMap tilt = tiltMapOf(stats);
  const GridSpec& g = stats.cells.grid;
  auto cost = [&](const char* name) { return ScoreMap::empty(g, name, "1"); };
  CostMaps m{cost("roughness"), cost("slope"), cost("body_advance"), cost("visibility"),
             cost("composite")};
  const auto& l = o.limits;
  const auto& w = o.weights;
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      const int i = g.index(r, c);
      if (!stats.valid[i] || !std::isfinite(criterion.score(r, c))) continue;
      const Eigen::Vector2d p = g.cellCenter(r, c);
      const double roughness = std::min(criterion.score(r, c) / o.roughness_scale, 1.0);
      const double slope = std::min(tilt.score(r, c) / o.foot.max_tilt_deg, 1.0);
      const double advance =
          1.0 - bodyAdvance(p, leg, l.reach_max_m, o.max_body_advance_m) / o.max_body_advance_m;
      const double visibility = leg.scanner ? linkInView(p, leg.shaft, *leg.scanner) : 0.0;
      m.roughness.score(r, c) = float(roughness);
      m.slope.score(r, c) = float(slope);
      m.body_advance.score(r, c) = float(advance);
      m.visibility.score(r, c) = float(visibility);
      // Discrete constraints (cmu-1990 Table 1) threshold the composite.
      const double reach = (p - leg.shaft).norm();
      const double contact = stats.reference_z + stats.top[i] - leg.reference_z;
      if (reach < l.reach_min_m || reach > l.reach_max_m || contact < l.elevation_min_m ||
          contact > l.elevation_max_m)
        continue;
      m.composite.score(r, c) = float(w.roughness * roughness + w.slope * slope +
                                      w.body_advance * advance + w.visibility * visibility);
    }
  return m;
}

}  // namespace ambler::footfall
