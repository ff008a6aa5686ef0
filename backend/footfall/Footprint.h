#pragma once

#include <vector>

#include "core/GridSpec.h"
#include "terrain/ElevationMap.h"

namespace ambler::footfall {

// The map cells under a flat disk foot centred on a cell: those whose
// centres lie within the disk. Symmetric about the centre, so the sums of
// x, y and xy over it vanish.
struct DiskFootprint {
  int radius_cells = 0;         // R: rows -R..R
  std::vector<int> half_width;  // per row dy + R: columns -w..w
  int cell_count = 0;           // N
  double sum_dx2 = 0.0;         // sum of dx^2 over the disk [cells^2], equal to that of dy^2

  // Throws std::invalid_argument unless diameter and resolution are > 0.
  static DiskFootprint forDiameter(double diameter_m, double resolution_m);
};

// The map's cells whose centres lie in a region: the candidate foot centres.
struct CandidateCells {
  GridSpec grid;      // the same cells as a grid of their own
  int first_row = 0;  // of the map
  int first_col = 0;
};

// Throws std::invalid_argument when the region holds no cell centre of the
// map or is not a finite, non-empty box.
CandidateCells candidateCells(const GridSpec& map_grid, const Box2& region);

// Whether candidateCells() finds any: the region is a finite box holding a
// cell centre of the map.
bool holdsCellCentre(const GridSpec& map_grid, const Box2& region);

// What every criterion needs about the terrain under the foot at each
// candidate centre, from row-wise prefix sums and running extremes (one pass
// over the region instead of one per footprint). Heights are relative to
// `reference_z`; the pessimistic surfaces are z_hi = z + k sigma (where the
// foot may first touch) and z_lo = z - k sigma (how deep the holes may be).
struct FootprintStatistics {
  CandidateCells cells;
  DiskFootprint disk;
  double reference_z = 0.0;  // [m]
  // Per candidate, row-major over cells.grid:
  std::vector<unsigned char> valid;                   // every cell under the foot is known
  std::vector<double> top;                            // max z_hi [m]
  std::vector<double> bottom;                         // min z_lo [m]
  std::vector<double> sum_z, sum_z2, sum_xz, sum_yz;  // x, y in cells from the centre
  std::vector<double> sum_lo, sum_xlo, sum_ylo;
  std::vector<double> sum_var;  // sum of sigma^2 [m^2]
  // The k-th highest z_lo with k = ceil(support_fraction N), resolved to
  // the request's support_bin_m (coarser if the relief needs more than 4
  // million bins) and rounded up to its bin's upper edge; empty unless
  // asked for.
  std::vector<double> kth_highest_lo;

  int size() const { return cells.grid.cellCount(); }
};

struct StatisticsRequest {
  double diameter_m = 0.30;
  double sigma_margin = 2.0;
  double support_fraction = 0.0;  // 0: no order statistic
  double support_bin_m = 5e-4;
  int clearance_cells = 0;  // cells between the sole and any cell not known
};

FootprintStatistics computeFootprintStatistics(const terrain::ElevationMap& map, const Box2& region,
                                               const StatisticsRequest& request);

}  // namespace ambler::footfall
