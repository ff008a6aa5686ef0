#pragma once

#include <optional>
#include <vector>

#include "io/Image.h"
#include "terrain/ElevationMap.h"

namespace ambler::terrain {

// How well a map matches ground truth on the same grid: the true height at
// each cell centre and the true state (0 visible, 1 outside the field of
// view, 2 occluded; the simulator's VisibilityTruth). Scores of several
// maps accumulate, so one score can pool a whole evaluation.
class MapScore {
 public:
  // Throws std::invalid_argument when the truth is not the map's size.
  // `score_sigma` false leaves the map out of the sigma calibration (maps of
  // noise-free scans, whose sigma is only the interpolation error bound).
  void add(const ElevationMap& map, const io::FloatImage& true_height,
           const io::ByteImage& true_state, bool score_sigma = true);

  // Root mean square of (elevation - true height) over known cells [m].
  std::optional<double> rmse() const;
  // Fraction of the truly visible cells the map knows.
  std::optional<double> coverage() const;
  // Fraction of the truly visible cells the map has as oblique: seen, but
  // not to stand on.
  std::optional<double> obliqueCoverage() const;
  // Over cells inside the field of view (true state 0 or 2): the fraction
  // of occluded cells marked shadow, and of shadow cells truly occluded.
  std::optional<double> shadowRecall() const;
  std::optional<double> shadowPrecision() const;
  // The same with a one-cell tolerance at the shadow's boundary: an
  // occluded cell counts as found when the map has shadow within one cell
  // (8-neighbourhood), a shadow cell as right when truth has an occluded
  // cell within one cell.
  std::optional<double> shadowRecallWithin1() const;
  std::optional<double> shadowPrecisionWithin1() const;
  // The share of the map's shadow cells that lie outside the field of view,
  // which the precisions above leave out: ground nobody could have seen
  // shown as hidden behind an occluder.
  std::optional<double> shadowOutOfView() const;
  // Safety: the fraction of truly occluded cells the map reports known
  // (their height is made up), and how many of those have no truly
  // visible cell within one cell.
  std::optional<double> occludedKnown() const;
  long occludedKnownFar() const { return occluded_known_far_; }
  // How far off the made-up heights are: the q-quantile (0..1) of
  // |elevation - true height| over the occluded cells reported known [m].
  std::optional<double> occludedKnownError(double q) const;
  // Standard deviation of error / sigma over known cells with sigma > 0;
  // 1 when the sigmas are honest.
  std::optional<double> sigmaCalibration() const;
  // The same over the truly visible cells alone: how honest sigma is where
  // the height was seen, apart from the occluded cells given a made-up one.
  std::optional<double> sigmaCalibrationVisible() const;
  long knownCells() const { return known_; }

 private:
  double sum_sq_ = 0.0;
  long known_ = 0;
  long visible_ = 0, visible_known_ = 0, visible_oblique_ = 0;
  long shadow_hit_ = 0, shadow_false_ = 0, shadow_missed_ = 0;
  long occluded_ = 0, occluded_found_ = 0, shadow_ = 0, shadow_right_ = 0;
  long shadow_out_of_view_ = 0;
  long occluded_known_ = 0, occluded_known_far_ = 0;
  std::vector<float> occluded_known_errors_;
  // Sums of error / sigma: over all known cells, and over the visible ones.
  struct RatioSums {
    double sum = 0.0, sum_sq = 0.0;
    long n = 0;
    void add(double ratio) { sum += ratio, sum_sq += ratio * ratio, ++n; }
    std::optional<double> standardDeviation() const;
  };
  RatioSums ratios_, visible_ratios_;
};

// Two maps of one scene compared on the cells both know: each one's RMSE
// there. Methods that know different cells (the locus method fills sparse
// far ground that binning leaves empty, where any estimate errs more) are
// compared on equal ground. Pools over scenes, as MapScore does.
class SharedCellsScore {
 public:
  // Throws std::invalid_argument when the maps or the truth differ in size.
  void add(const ElevationMap& first, const ElevationMap& second,
           const io::FloatImage& true_height);
  std::optional<double> rmseFirst() const;
  std::optional<double> rmseSecond() const;
  long cells() const { return cells_; }

 private:
  double sum_sq_first_ = 0.0, sum_sq_second_ = 0.0;
  long cells_ = 0;
};

}  // namespace ambler::terrain
