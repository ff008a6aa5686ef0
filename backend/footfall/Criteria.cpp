#include "footfall/Criteria.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "footfall/Footprint.h"

namespace ambler::footfall {

namespace {

constexpr std::array<std::string_view, 5> kNames{"maxmin", "planar", "support", "freevolume",
                                                 "equilibrium"};

// Least-squares plane z = a x + b y + c under the foot. Over the symmetric
// disk the normal equations decouple: a = sum(xz) / sum(x^2), likewise b.
struct PlaneFit {
  double rms = 0.0;       // of the residuals [m]
  double tilt_deg = 0.0;  // of the normal from the vertical
};

PlaneFit fitPlane(const FootprintStatistics& s, int i) {
  const double n = s.disk.cell_count, sxx = s.disk.sum_dx2;
  const double a = sxx > 0 ? s.sum_xz[i] / sxx : 0.0, b = sxx > 0 ? s.sum_yz[i] / sxx : 0.0;
  const double residual =
      s.sum_z2[i] - s.sum_z[i] * s.sum_z[i] / n - a * s.sum_xz[i] - b * s.sum_yz[i];
  const double slope = std::hypot(a, b) / s.cells.grid.resolution;
  return {std::sqrt(std::max(residual, 0.0) / n), std::atan(slope) * 180.0 / M_PI};
}

// Score of one criterion at candidate i (valid), in the criterion's unit.
double scoreAt(const FootprintStatistics& s, int i, Criterion criterion, const FootOptions& o) {
  const double n = s.disk.cell_count, res = s.cells.grid.resolution, cell_area = res * res;
  // V = N z_max - sum z_i, as a volume (times the cell area).
  auto freeVolume = [&] { return (n * s.top[i] - s.sum_lo[i]) * cell_area; };
  switch (criterion) {
    case Criterion::kMaxMin:
      return s.top[i] - s.bottom[i];
    case Criterion::kPlanarFit: {
      const PlaneFit fit = fitPlane(s, i);
      if (fit.tilt_deg > o.max_tilt_deg) return NAN;
      return fit.rms + o.sigma_margin * std::sqrt(s.sum_var[i] / n);
    }
    case Criterion::kSupportArea:  // d_opt: lower the foot from the top until A_min
      return std::max(s.top[i] - s.kth_highest_lo[i], 0.0);
    case Criterion::kFreeVolume:
      return freeVolume();
    case Criterion::kEquilibrium: {
      // m_x = sum x_i (z_max - z_i) = -sum x_i z_i, since sum x_i = 0.
      const double moment = std::hypot(s.sum_xlo[i], s.sum_ylo[i]) * res * cell_area;
      return freeVolume() + o.equilibrium_moment_weight * moment / (o.diameter_m / 2);
    }
  }
  return NAN;
}

void requireRange(bool ok, const char* field, const char* range) {
  if (!ok)
    throw std::invalid_argument(std::string("footfall option ") + field + " must be " + range);
}

}  // namespace

std::string_view criterionName(Criterion criterion) { return kNames[int(criterion)]; }

std::optional<Criterion> criterionFromName(std::string_view name) {
  for (int i = 0; i < int(kNames.size()); ++i)
    if (kNames[i] == name) return Criterion(i);
  return std::nullopt;
}

std::string_view criterionUnit(Criterion criterion) {
  return criterion == Criterion::kFreeVolume || criterion == Criterion::kEquilibrium ? "m^3" : "m";
}

void validate(const FootOptions& o) {
  requireRange(o.diameter_m > 0 && o.diameter_m <= 5, "diameter_m", "in (0, 5] m");
  requireRange(o.min_support_fraction > 0 && o.min_support_fraction <= 1, "min_support_fraction",
               "in (0, 1]");
  requireRange(o.max_tilt_deg > 0 && o.max_tilt_deg < 90, "max_tilt_deg", "in (0, 90) deg");
  requireRange(o.sigma_margin >= 0 && o.sigma_margin <= 10, "sigma_margin", "in [0, 10]");
  requireRange(o.equilibrium_moment_weight >= 0 && o.equilibrium_moment_weight <= 100,
               "equilibrium_moment_weight", "in [0, 100]");
  requireRange(o.support_bin_m >= 1e-6 && o.support_bin_m <= 0.1, "support_bin_m",
               "in [1e-6, 0.1] m");
  requireRange(o.clearance_m >= 0 && o.clearance_m <= 1, "clearance_m", "in [0, 1] m");
}

ScoreMap ScoreMap::empty(const GridSpec& grid, std::string name, std::string unit) {
  return {grid, terrain::Layer::Constant(grid.rows, grid.cols, NAN), std::move(name),
          std::move(unit)};
}

FootprintStatistics footprintStatistics(const terrain::ElevationMap& map, const Box2& region,
                                        const FootOptions& o, bool with_support) {
  validate(o);
  const int clearance = int(std::floor(o.clearance_m / map.grid().resolution + 1e-9));
  return computeFootprintStatistics(
      map, region,
      {o.diameter_m, o.sigma_margin, with_support ? o.min_support_fraction : 0.0, o.support_bin_m,
       clearance});
}

int ScoreMap::validCount() const {
  int n = 0;
  for (int i = 0; i < score.size(); ++i) n += std::isfinite(score.data()[i]) ? 1 : 0;
  return n;
}

Foothold bestFoothold(const ScoreMap& map) {
  Foothold best;
  const Eigen::Vector2d centre(map.grid.origin_x + map.grid.cols * map.grid.resolution / 2,
                               map.grid.origin_y + map.grid.rows * map.grid.resolution / 2);
  double best_distance = INFINITY;
  for (int r = 0; r < map.grid.rows; ++r)
    for (int c = 0; c < map.grid.cols; ++c) {
      const double v = map.score(r, c);
      if (!std::isfinite(v) || (best.found && v > best.score)) continue;
      const Eigen::Vector2d p = map.grid.cellCenter(r, c);
      const double distance = (p - centre).squaredNorm();
      if (best.found && v == best.score && distance >= best_distance) continue;
      best = {true, p.x(), p.y(), v, r, c};
      best_distance = distance;
    }
  return best;
}

ScoreMap evaluateFootfalls(const terrain::ElevationMap& map, const Box2& region,
                           Criterion criterion, const FootOptions& options) {
  const auto s = footprintStatistics(map, region, options, criterion == Criterion::kSupportArea);
  return scoreMapOf(s, criterion, options);
}

std::vector<ScoreMap> evaluateAllCriteria(const terrain::ElevationMap& map, const Box2& region,
                                          const FootOptions& options) {
  const auto s = footprintStatistics(map, region, options, true);
  std::vector<ScoreMap> maps;
  for (const Criterion c : kAllCriteria) maps.push_back(scoreMapOf(s, c, options));
  return maps;
}

ScoreMap planeTilt(const terrain::ElevationMap& map, const Box2& region,
                   const FootOptions& options) {
  return tiltMapOf(footprintStatistics(map, region, options, false));
}

ScoreMap scoreMapOf(const FootprintStatistics& s, Criterion criterion, const FootOptions& o) {
  ScoreMap m = ScoreMap::empty(s.cells.grid, std::string(criterionName(criterion)),
                               std::string(criterionUnit(criterion)));
  for (int i = 0; i < s.size(); ++i)
    if (s.valid[i]) m.score.data()[i] = float(scoreAt(s, i, criterion, o));
  return m;
}

ScoreMap tiltMapOf(const FootprintStatistics& s) {
  ScoreMap m = ScoreMap::empty(s.cells.grid, "slope", "deg");
  for (int i = 0; i < s.size(); ++i)
    if (s.valid[i]) m.score.data()[i] = float(fitPlane(s, i).tilt_deg);
  return m;
}

}  // namespace ambler::footfall
