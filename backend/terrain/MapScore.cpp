#include "terrain/MapScore.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ambler::terrain {

namespace {
std::optional<double> ratio(double numerator, long denominator) {
  if (denominator == 0) return std::nullopt;
  return numerator / double(denominator);
}

// Whether pred holds for a cell within one cell of (r, c), itself included.
template <class Pred>
bool near(const GridSpec& g, int r, int c, Pred&& pred) {
  for (int rr = std::max(0, r - 1); rr <= std::min(g.rows - 1, r + 1); ++rr)
    for (int cc = std::max(0, c - 1); cc <= std::min(g.cols - 1, c + 1); ++cc)
      if (pred(rr, cc)) return true;
  return false;
}
}  // namespace

void MapScore::add(const ElevationMap& map, const io::FloatImage& true_height,
                   const io::ByteImage& true_state, bool score_sigma) {
  const auto& g = map.grid();
  if (true_height.rows != g.rows || true_height.cols != g.cols || true_state.rows != g.rows ||
      true_state.cols != g.cols)
    throw std::invalid_argument("ground truth is not the size of the map");
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      const int truth = true_state(r, c);
      const auto state = map.state(r, c);
      if (truth == 0) ++visible_, visible_oblique_ += state == CellState::kOblique;
      shadow_out_of_view_ += truth == 1 && state == CellState::kShadow;
      if (truth != 1) {
        const bool shadow = state == CellState::kShadow, occluded = truth == 2;
        shadow_hit_ += shadow && occluded;
        shadow_false_ += shadow && !occluded;
        shadow_missed_ += !shadow && occluded;
        if (occluded) {
          ++occluded_;
          occluded_found_ += near(
              g, r, c, [&](int rr, int cc) { return map.state(rr, cc) == CellState::kShadow; });
        }
        if (shadow) {
          ++shadow_;
          shadow_right_ += near(g, r, c, [&](int rr, int cc) { return true_state(rr, cc) == 2; });
        }
        if (occluded && state == CellState::kKnown) {
          ++occluded_known_;
          occluded_known_far_ +=
              !near(g, r, c, [&](int rr, int cc) { return true_state(rr, cc) == 0; });
        }
      }
      if (state != CellState::kKnown || !std::isfinite(true_height(r, c))) continue;
      visible_known_ += truth == 0;
      const double error = double(map.elevation(r, c)) - true_height(r, c);
      sum_sq_ += error * error;
      if (truth == 2) occluded_known_errors_.push_back(float(std::abs(error)));
      ++known_;
      const double sigma = map.sigma(r, c);
      if (score_sigma && sigma > 0 && std::isfinite(sigma)) {
        ratios_.add(error / sigma);
        if (truth == 0) visible_ratios_.add(error / sigma);
      }
    }
}

std::optional<double> MapScore::rmse() const {
  if (known_ == 0) return std::nullopt;
  return std::sqrt(sum_sq_ / double(known_));
}

std::optional<double> MapScore::coverage() const { return ratio(double(visible_known_), visible_); }

std::optional<double> MapScore::obliqueCoverage() const {
  return ratio(double(visible_oblique_), visible_);
}

std::optional<double> MapScore::shadowRecall() const {
  return ratio(double(shadow_hit_), shadow_hit_ + shadow_missed_);
}

std::optional<double> MapScore::shadowPrecision() const {
  return ratio(double(shadow_hit_), shadow_hit_ + shadow_false_);
}

std::optional<double> MapScore::shadowRecallWithin1() const {
  return ratio(double(occluded_found_), occluded_);
}

std::optional<double> MapScore::shadowPrecisionWithin1() const {
  return ratio(double(shadow_right_), shadow_);
}

std::optional<double> MapScore::shadowOutOfView() const {
  return ratio(double(shadow_out_of_view_), shadow_ + shadow_out_of_view_);
}

std::optional<double> MapScore::occludedKnown() const {
  return ratio(double(occluded_known_), occluded_);
}

std::optional<double> MapScore::occludedKnownError(double q) const {
  if (occluded_known_errors_.empty() || !(q >= 0.0 && q <= 1.0)) return std::nullopt;
  auto errors = occluded_known_errors_;
  const auto k = std::size_t(std::lround(q * double(errors.size() - 1)));
  std::nth_element(errors.begin(), errors.begin() + long(k), errors.end());
  return errors[k];
}

std::optional<double> MapScore::RatioSums::standardDeviation() const {
  if (n < 2) return std::nullopt;
  const double mean = sum / double(n);
  const double variance = (sum_sq - double(n) * mean * mean) / double(n - 1);
  return std::sqrt(std::max(variance, 0.0));
}

std::optional<double> MapScore::sigmaCalibration() const { return ratios_.standardDeviation(); }

std::optional<double> MapScore::sigmaCalibrationVisible() const {
  return visible_ratios_.standardDeviation();
}

void SharedCellsScore::add(const ElevationMap& first, const ElevationMap& second,
                           const io::FloatImage& true_height) {
  const auto& g = first.grid();
  const auto& h = second.grid();
  if (h.rows != g.rows || h.cols != g.cols || true_height.rows != g.rows ||
      true_height.cols != g.cols)
    throw std::invalid_argument("the two maps and the truth are not of one size");
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      if (!first.isKnown(r, c) || !second.isKnown(r, c) || !std::isfinite(true_height(r, c)))
        continue;
      const double a = double(first.elevation(r, c)) - true_height(r, c);
      const double b = double(second.elevation(r, c)) - true_height(r, c);
      sum_sq_first_ += a * a, sum_sq_second_ += b * b, ++cells_;
    }
}

std::optional<double> SharedCellsScore::rmseFirst() const {
  if (cells_ == 0) return std::nullopt;
  return std::sqrt(sum_sq_first_ / double(cells_));
}

std::optional<double> SharedCellsScore::rmseSecond() const {
  if (cells_ == 0) return std::nullopt;
  return std::sqrt(sum_sq_second_ / double(cells_));
}

}  // namespace ambler::terrain
