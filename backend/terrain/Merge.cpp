#include "terrain/Merge.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/Region.h"
#include "terrain/Locus.h"

namespace ambler::terrain {

namespace {
constexpr double kMinSigma = 1e-6;  // [m]
}

void mergeInto(ElevationMap& map, const ElevationMap& update) {
  if (map.frame() != update.frame())
    throw std::invalid_argument("cannot merge a map in frame '" + update.frame() +
                                "' into one in frame '" + map.frame() + "'");
  const GridSpec& grid = map.grid();
  // Only the map cells under the update: a view is small next to a local
  // terrain map the rover carries along.
  forEachCellIn(grid, update.grid().bounds(), [&](int r, int c) {
    const auto p = grid.cellCenter(r, c);
    const auto source = update.grid().cellAt(p.x(), p.y());
    if (!source) return;
    const int ur = source->row, uc = source->col;
    const auto incoming = update.state(ur, uc);
    if (incoming == CellState::kUnknown) return;
    if (incoming == CellState::kShadow) {
      if (map.state(r, c) == CellState::kUnknown) map.setUnobserved(r, c, CellState::kShadow);
      return;
    }
    const double z_b = update.elevation(ur, uc);
    const double s_b = std::max<double>(update.sigma(ur, uc), kMinSigma);
    const float n_b = update.count(ur, uc);
    if (!map.hasHeight(r, c)) {
      map.setHeight(r, c, incoming, z_b, s_b, n_b);
      return;
    }
    const auto state = map.isKnown(r, c) ? CellState::kKnown : incoming;
    const double s_a = std::max<double>(map.sigma(r, c), kMinSigma);
    const double w_a = 1.0 / (s_a * s_a), w_b = 1.0 / (s_b * s_b);
    const double z = (w_a * map.elevation(r, c) + w_b * z_b) / (w_a + w_b);
    map.setHeight(r, c, state, z, 1.0 / std::sqrt(w_a + w_b), map.count(r, c) + n_b);
  });
}

GridSpec mergeScan(ElevationMap& traverse, const sensor::RangeImage& scan) {
  Box2 returns{INFINITY, INFINITY, -INFINITY, -INFINITY};
  for (const auto& p : scan.pointsInWorld()) {
    returns.x_min = std::min(returns.x_min, p.x()), returns.x_max = std::max(returns.x_max, p.x());
    returns.y_min = std::min(returns.y_min, p.y()), returns.y_max = std::max(returns.y_max, p.y());
  }
  const GridSpec window = traverse.grid().window(returns);
  if (window.cellCount() > 0) mergeInto(traverse, buildLocusMap(scan, window));
  return window;
}

}  // namespace ambler::terrain
