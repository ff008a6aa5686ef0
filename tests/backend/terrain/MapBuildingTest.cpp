// The parts around the locus method: edge detection, the binning baseline
// and scoring against ground truth.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/Angles.h"
#include "terrain/Binning.h"
#include "terrain/MapScore.h"
#include "terrain/OccludingEdges.h"

namespace ambler::terrain {
namespace {

// A range image looking down from 5 m at flat ground z = 0, exact ranges.
sensor::RangeImage flatGroundImage(int rows, int cols) {
  sensor::RangeImage image;
  image.geometry = sensor::ScanGeometry::symmetric(rows, cols, 30 * kDeg, 40 * kDeg);
  image.sensor_to_world =
      Eigen::Translation3d(0, 0, 5) * Eigen::AngleAxisd(-30 * kDeg, Eigen::Vector3d::UnitX());
  image.range.resize(std::size_t(rows) * cols);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const Eigen::Vector3d d =
          image.sensor_to_world.linear() *
          sensor::toCartesian({1.0, image.geometry.phi(r), image.geometry.theta(c)});
      image.range[std::size_t(r) * cols + c] = float(5.0 / -d.z());
    }
  return image;
}

TEST(OccludingEdges, ContinuousGroundHasNoEdgesAndAStepHas) {
  auto image = flatGroundImage(64, 64);
  EXPECT_EQ(OccludingEdges(image).edgePixelCount(), 0);
  // Rows 0..19 see something 2 m farther: a range shadow boundary between
  // rows 19 and 20.
  for (int r = 0; r < 20; ++r)
    for (int c = 0; c < 64; ++c) image.range[std::size_t(r) * 64 + c] += 2.0f;
  const OccludingEdges edges(image);
  for (int c = 0; c < 63; ++c) {
    EXPECT_TRUE(edges.quadIsEdge(19, c)) << c;
    EXPECT_FALSE(edges.quadIsEdge(10, c)) << c;
    EXPECT_FALSE(edges.quadIsEdge(30, c)) << c;
  }
  EXPECT_EQ(edges.edgePixelCount(), 2 * 64);
  for (int c = 0; c < 63; ++c) EXPECT_FALSE(edges.rightPairIsEdge(19, c)) << c;  // along it
}

// Columns 40..63 see something 2 m farther: each scanline crosses an edge
// between columns 39 and 40, and only there.
TEST(OccludingEdges, AJumpBetweenColumnsIsARightPairEdge) {
  auto image = flatGroundImage(64, 64);
  for (int r = 0; r < 64; ++r)
    for (int c = 40; c < 64; ++c) image.range[std::size_t(r) * 64 + c] += 2.0f;
  const OccludingEdges edges(image);
  for (int r = 0; r < 64; ++r)
    for (int c = 0; c < 63; ++c) EXPECT_EQ(edges.rightPairIsEdge(r, c), c == 39) << r << "," << c;
}

// A jump between the weak and the strong noise allowance is an edge with
// hysteresis on when it runs along the image, never when it is alone.
TEST(OccludingEdges, HysteresisKeepsWeakJumpsThatContinue) {
  auto image = flatGroundImage(64, 64);
  const double jump = 2.4;
  const double a = image.range[std::size_t(20) * 64 + 32], b = a + jump;
  // Noise so that the jump is 3 sigma of the pair's difference.
  image.range_sigma_k = jump / (3 * std::sqrt(a * a * a * a + b * b * b * b));
  for (int c = 24; c <= 40; ++c)
    for (int r = 0; r < 20; ++r) image.range[std::size_t(r) * 64 + c] += float(jump);
  for (int r = 0; r < 20; ++r) image.range[std::size_t(r) * 64 + 52] += float(jump);  // alone

  OccludingEdgeOptions off;
  off.weak_noise_sigmas = off.noise_sigmas;
  EXPECT_EQ(OccludingEdges(image, off).edgePixelCount(), 0);
  const OccludingEdges edges(image);  // default: 4 sigma, or 2 where a jump continues
  for (int c = 26; c <= 38; ++c) EXPECT_TRUE(edges.pixelIsEdge(19, c)) << c;
  EXPECT_FALSE(edges.pixelIsEdge(19, 52));
  EXPECT_FALSE(edges.pixelIsEdge(10, 32));
}

// Rows 0..19 of `column` pushed away so that the pair across rows 19 and 20
// is `sigmas` beyond the grazing bound of the default options.
void pushBeyondTheGrazingBound(sensor::RangeImage& image, int column, double sigmas) {
  const int cols = image.geometry.cols;
  const double near = image.range[std::size_t(20) * cols + column];
  const double separation =
      std::abs(image.geometry.phi_step) * std::cos(image.geometry.theta(column));
  const double bound = near * separation / std::tan(OccludingEdgeOptions{}.min_grazing_deg * kDeg);
  double jump = bound;
  for (int i = 0; i < 20; ++i) {  // the noise grows with the far range
    const double far = near + jump;
    jump = bound + sigmas * image.range_sigma_k * std::sqrt(std::pow(near, 4) + std::pow(far, 4));
  }
  const float push = float(near + jump) - image.range[std::size_t(19) * cols + column];
  for (int r = 0; r < 20; ++r) image.range[std::size_t(r) * cols + column] += push;
}

// A pair beyond the grazing bound by less than the grazing noise allowance
// is grazing only beside a grazing pair of the same kind.
TEST(OccludingEdges, HysteresisKeepsWeakGrazingPairsBesideAGrazingOne) {
  auto image = flatGroundImage(64, 64);
  image.range_sigma_k = 2e-4;
  for (int c = 24; c <= 40; ++c) pushBeyondTheGrazingBound(image, c, c == 32 ? 1.75 : 0.75);
  for (int c = 50; c <= 54; ++c) pushBeyondTheGrazingBound(image, c, 0.75);

  // The step behind each pushed column is a pocket whose far side faces
  // the sensor: the concave turn's rule, off here, would find each alone.
  OccludingEdgeOptions defaults;
  defaults.concave_turn_deg = 0.0;
  OccludingEdgeOptions off = defaults;
  off.weak_grazing_noise_sigmas = off.grazing_noise_sigmas;
  off.weak_grazing_deg = off.min_grazing_deg;
  const OccludingEdges strict(image, off);
  const OccludingEdges edges(image, defaults);  // 1.5 sigma, or 0 beside a grazing pair
  EXPECT_EQ(edges.edgePixelCount(), 0);
  for (int c = 0; c < 63; ++c) {
    // A row pair marks the quads left and right of it.
    EXPECT_EQ(strict.quadIsGrazing(19, c), c == 31 || c == 32) << c;
    EXPECT_EQ(edges.quadIsGrazing(19, c), c >= 30 && c <= 33) << c;
    EXPECT_FALSE(edges.quadIsGrazing(10, c)) << c;
  }
  off.weak_grazing_noise_sigmas = off.grazing_noise_sigmas + 0.5;
  EXPECT_THROW(OccludingEdges(image, off), std::invalid_argument);
}

// Rows 0..near_row - 1 of `column` pushed away so that, without noise, the
// pair across rows near_row - 1 and near_row is ground seen at `grazing_deg`.
void seeRowPairAbove(sensor::RangeImage& image, int column, int near_row, double grazing_deg) {
  const int cols = image.geometry.cols;
  const double near = image.range[std::size_t(near_row) * cols + column];
  const double separation =
      std::abs(image.geometry.phi_step) * std::cos(image.geometry.theta(column));
  const double jump = near * separation / std::tan(grazing_deg * kDeg);
  const float push = float(near + jump) - image.range[std::size_t(near_row - 1) * cols + column];
  for (int r = 0; r < near_row; ++r) image.range[std::size_t(r) * cols + column] += push;
}

// Rows 0..19 of `column` pushed away so that, without noise, the pair
// across rows 19 and 20 is ground seen at `grazing_deg`.
void seeRowPairAt(sensor::RangeImage& image, int column, double grazing_deg) {
  seeRowPairAbove(image, column, 20, grazing_deg);
}

// A swell's back slope seen just above the grazing bound (12 deg against
// 10) is grazing beside a pair below the bound, with the weak angle at 13
// deg (the default); alone, or with the weak angle off, it is continuous
// ground.
TEST(OccludingEdges, AWeakGrazingAngleCountsBesideAGrazingPair) {
  auto image = flatGroundImage(64, 64);
  for (int c = 24; c <= 40; ++c) seeRowPairAt(image, c, c == 32 ? 9.0 : 12.0);
  for (int c = 50; c <= 54; ++c) seeRowPairAt(image, c, 12.0);

  OccludingEdgeOptions beside;  // the concave turn's rule, measured alone below, off
  beside.concave_turn_deg = 0.0;
  OccludingEdgeOptions options = beside;
  options.weak_grazing_deg = options.min_grazing_deg;
  const OccludingEdges off(image, options);
  const OccludingEdges edges(image, beside);  // 13 deg beside a grazing pair
  EXPECT_EQ(edges.edgePixelCount(), 0);
  for (int c = 0; c < 63; ++c) {
    EXPECT_EQ(off.quadIsGrazing(19, c), c == 31 || c == 32) << c;
    EXPECT_EQ(edges.quadIsGrazing(19, c), c >= 30 && c <= 33) << c;
    EXPECT_FALSE(edges.quadIsGrazing(10, c)) << c;
  }
  options.weak_grazing_deg = 11.0;  // 12 deg is no longer weak grazing
  const OccludingEdges narrow(image, options);
  for (int c = 0; c < 63; ++c) EXPECT_EQ(narrow.quadIsGrazing(19, c), c == 31 || c == 32) << c;
  for (const double bad : {0.0, 90.0, double(NAN)}) {
    options.weak_grazing_deg = bad;
    EXPECT_THROW(OccludingEdges(image, options), std::invalid_argument) << bad;
  }
}

// Rows 0..19 of `column` pushed away as by seeRowPairAt(), and rows 0..18
// further, so that the next pair farther out, across rows 18 and 19, is
// ground seen at `far_deg`.
void seeRowPairsAt(sensor::RangeImage& image, int column, double near_deg, double far_deg) {
  seeRowPairAt(image, column, near_deg);
  seeRowPairAbove(image, column, 19, far_deg);
}

// A pair seen at 12 deg (under the weak angle of 13) whose next pair
// farther out is seen at 20 deg is grazing alone: the ground turns back
// toward the sensor behind it by 8 deg, more than the 4 of the default.
// By 2 deg it is not, nor with the rule off; under noise, a turn of 4.2
// deg is grazing only while it stands beyond the allowance.
TEST(OccludingEdges, AConcaveTurnBehindAWeakGrazingPairMakesItGrazing) {
  auto image = flatGroundImage(64, 64);
  for (int c = 10; c <= 14; ++c) seeRowPairsAt(image, c, 12.0, 20.0);
  for (int c = 30; c <= 34; ++c) seeRowPairsAt(image, c, 12.0, 14.0);
  for (int c = 50; c <= 54; ++c) seeRowPairsAt(image, c, 12.0, 16.2);

  const OccludingEdges edges(image);
  OccludingEdgeOptions options;
  options.concave_turn_deg = 0.0;
  const OccludingEdges off(image, options);
  EXPECT_EQ(edges.edgePixelCount(), 0);
  for (int c = 0; c < 63; ++c) {
    // A row pair marks the quads left and right of it.
    EXPECT_EQ(edges.quadIsGrazing(19, c), (c >= 9 && c <= 14) || (c >= 49 && c <= 54)) << c;
    EXPECT_FALSE(off.quadIsGrazing(19, c)) << c;
    EXPECT_FALSE(edges.quadIsGrazing(18, c)) << c;  // 20 deg: no grazing ground
  }

  // Noise whose allowance (1.5 sigma) is a quarter of the 12 deg pair's
  // margin under the weak angle: that pair stays weak grazing, the 8 deg
  // turn stands beyond the noise, the 4.2 deg one does not.
  const int cols = image.geometry.cols;
  const double a = image.range[std::size_t(20) * cols + 52];
  const double b = image.range[std::size_t(19) * cols + 52];
  const double separation = std::abs(image.geometry.phi_step) * std::cos(image.geometry.theta(52));
  const double margin = a * separation * (1 / std::tan(12 * kDeg) - 1 / std::tan(13 * kDeg));
  image.range_sigma_k = 0.25 * margin / (1.5 * std::sqrt(std::pow(a, 4) + std::pow(b, 4)));
  const OccludingEdges noisy(image);
  for (int c = 0; c < 63; ++c) EXPECT_EQ(noisy.quadIsGrazing(19, c), c >= 9 && c <= 14) << c;

  for (const double bad : {-1.0, 90.0, double(NAN)}) {
    options.concave_turn_deg = bad;
    EXPECT_THROW(OccludingEdges(image, options), std::invalid_argument) << bad;
  }
}

// Ground whose range grows by `ratio` times the grazing bound from one
// scanline to the next (ratio > 1: seen more obliquely than the bound), with
// noise so large that one pair cannot tell: its excess over the bound is
// a quarter of a standard deviation of the pair's difference near the
// middle row.
sensor::RangeImage obliqueGroundImage(double ratio, unsigned seed) {
  const int rows = 64, cols = 32;
  sensor::RangeImage image;
  image.geometry = sensor::ScanGeometry::symmetric(rows, cols, 8 * kDeg, 20 * kDeg);
  const double per_rho =
      std::abs(image.geometry.phi_step) / std::tan(OccludingEdgeOptions{}.min_grazing_deg * kDeg);
  const double middle = 10.0 * std::pow(1 + ratio * per_rho, rows / 2);
  image.range_sigma_k = std::abs(ratio - 1) * per_rho / (0.25 * std::sqrt(2.0) * middle);
  std::mt19937 draw(seed);
  std::normal_distribution<double> normal;
  image.range.resize(std::size_t(rows) * cols);
  for (int c = 0; c < cols; ++c) {
    double rho = 10.0;
    for (int r = rows - 1; r >= 0; --r, rho *= 1 + ratio * per_rho)  // row 0 looks highest
      image.range[std::size_t(r) * cols + c] =
          float(rho + image.range_sigma_k * rho * rho * normal(draw));
  }
  return image;
}

// Of the quads away from the image's top and bottom 8 scanlines.
double grazingShare(const sensor::RangeImage& image, const OccludingEdgeOptions& options = {}) {
  const OccludingEdges edges(image, options);
  int grazing = 0, quads = 0;
  for (int r = 8; r < image.rows() - 9; ++r)
    for (int c = 0; c < image.cols() - 1; ++c) grazing += edges.quadIsGrazing(r, c), ++quads;
  return double(grazing) / quads;
}

// Under that noise the pairs alone (with their hysteresis) leave 40 % of
// the oblique ground known; the step averaged over 16 scanlines finds
// nearly all of it, and adds nothing on ground seen less obliquely than
// the bound, where noise alone makes a quarter of the quads grazing.
TEST(OccludingEdges, AnAveragedStepFindsGrazingGroundThatNoiseHidesFromPairs) {
  OccludingEdgeOptions pairs_only;
  pairs_only.grazing_baseline_rows = 0;
  const auto oblique = obliqueGroundImage(1.3, 7);
  EXPECT_LT(grazingShare(oblique, pairs_only), 0.7);  // 0.60
  EXPECT_GT(grazingShare(oblique), 0.95);             // 0.99
  const auto steeper = obliqueGroundImage(0.7, 7);
  EXPECT_DOUBLE_EQ(grazingShare(steeper), grazingShare(steeper, pairs_only));
  OccludingEdgeOptions one_row;
  one_row.grazing_baseline_rows = 1;
  EXPECT_THROW(OccludingEdges(oblique, one_row), std::invalid_argument);
}

TEST(Binning, AveragesThePointsInEachCell) {
  const auto image = flatGroundImage(64, 64);
  const auto map = buildBinnedMap(image, GridSpec::covering({-2, 6, 2, 12}, 0.5));
  ASSERT_GT(map.knownCount(), 50);
  for (int r = 0; r < map.grid().rows; ++r)
    for (int c = 0; c < map.grid().cols; ++c)
      if (map.isKnown(r, c)) {
        EXPECT_NEAR(map.elevation(r, c), 0.0, 1e-5);
        EXPECT_GE(map.count(r, c), 1);
      }
}

TEST(MapScore, CountsAgainstTruth) {
  ElevationMap map(GridSpec::covering({0, 0, 4, 1}, 1.0));
  map.setKnown(0, 0, 1.0, 0.5);                 // visible, error 1
  map.setUnobserved(0, 1, CellState::kShadow);  // occluded: a hit
  map.setUnobserved(0, 2, CellState::kShadow);  // visible: a false shadow
  io::FloatImage height(1, 4, 0.0f);
  io::ByteImage state(1, 4, 0);
  state(0, 1) = 2;
  state(0, 3) = 2;  // occluded, map unknown: a miss
  MapScore score;
  score.add(map, height, state);
  EXPECT_DOUBLE_EQ(*score.rmse(), 1.0);
  EXPECT_DOUBLE_EQ(*score.coverage(), 0.5);
  EXPECT_DOUBLE_EQ(*score.shadowRecall(), 0.5);
  EXPECT_DOUBLE_EQ(*score.shadowPrecision(), 0.5);
  EXPECT_DOUBLE_EQ(*score.shadowOutOfView(), 0.0);
  EXPECT_FALSE(score.sigmaCalibration());  // one ratio is not a spread
  EXPECT_THROW(score.add(map, io::FloatImage(2, 2), state), std::invalid_argument);
}

// Each map's RMSE over the cells both know: the cells only one of them
// knows, and cells without a true height, do not count.
TEST(SharedCellsScore, ComparesTwoMapsOnTheCellsBothKnow) {
  const GridSpec grid = GridSpec::covering({0, 0, 4, 1}, 1.0);
  ElevationMap first(grid), second(grid);
  io::FloatImage height(1, 4, 0.0f);
  height(0, 3) = NAN;
  first.setKnown(0, 0, 0.3, 0.1), second.setKnown(0, 0, 0.1, 0.1);
  first.setKnown(0, 1, 0.4, 0.1), second.setKnown(0, 1, -0.1, 0.1);
  first.setKnown(0, 2, 5.0, 0.1);  // only the first knows it
  first.setKnown(0, 3, 5.0, 0.1), second.setKnown(0, 3, 5.0, 0.1);
  SharedCellsScore score;
  EXPECT_FALSE(score.rmseFirst());
  score.add(first, second, height);
  EXPECT_EQ(score.cells(), 2);
  EXPECT_NEAR(*score.rmseFirst(), std::sqrt((0.09 + 0.16) / 2), 1e-6);
  EXPECT_NEAR(*score.rmseSecond(), std::sqrt((0.01 + 0.01) / 2), 1e-6);
  const ElevationMap other(GridSpec::covering({0, 0, 2, 1}, 1.0));
  EXPECT_THROW(score.add(first, other, height), std::invalid_argument);
}

TEST(MapScore, ToleratesOneCellAtShadowBoundariesAndCountsMadeUpCells) {
  ElevationMap map(GridSpec::covering({0, 0, 8, 1}, 1.0));
  io::FloatImage height(1, 8, 0.0f);
  //                        0  1  2  3  4  5  6  7
  io::ByteImage state(1, 8, 0);
  for (int c : {1, 3, 4, 5}) state(0, c) = 2;
  state(0, 7) = 1;
  for (int c : {0, 4, 5, 6}) map.setKnown(0, c, 0.0, 0.1);
  for (int c : {1, 2, 7}) map.setUnobserved(0, c, CellState::kShadow);
  MapScore score;
  score.add(map, height, state);
  EXPECT_DOUBLE_EQ(*score.shadowRecall(), 0.25);  // only cell 1
  EXPECT_DOUBLE_EQ(*score.shadowPrecision(), 0.5);
  // Cell 3 has shadow next to it; cells 4 and 5 do not.
  EXPECT_DOUBLE_EQ(*score.shadowRecallWithin1(), 0.5);
  // Cell 2 is visible but next to occluded cells; cell 7 is outside view.
  EXPECT_DOUBLE_EQ(*score.shadowPrecisionWithin1(), 1.0);
  // Of the three shadow cells, cell 7.
  EXPECT_DOUBLE_EQ(*score.shadowOutOfView(), 1.0 / 3);
  // Cells 4 and 5 are occluded and reported known; 4 has no visible cell
  // next to it.
  EXPECT_DOUBLE_EQ(*score.occludedKnown(), 0.5);
  EXPECT_EQ(score.occludedKnownFar(), 1);
}

// The made-up heights' errors, by quantile: only occluded cells reported
// known count, whatever the error of the cells that were seen.
TEST(MapScore, QuantilesOfTheMadeUpHeightsErrors) {
  ElevationMap map(GridSpec::covering({0, 0, 6, 1}, 1.0));
  io::FloatImage height(1, 6, 0.0f);
  io::ByteImage state(1, 6, 2);
  state(0, 0) = 0;
  map.setKnown(0, 0, 9.0, 0.1);  // seen: not counted
  const float made_up[] = {0.0f, -0.1f, 0.2f, -0.4f, 0.3f};
  for (int c = 1; c < 6; ++c) map.setKnown(0, c, made_up[c - 1], 0.1);
  MapScore score;
  EXPECT_FALSE(score.occludedKnownError(0.5));
  score.add(map, height, state);
  EXPECT_FLOAT_EQ(*score.occludedKnownError(0.0), 0.0f);
  EXPECT_FLOAT_EQ(*score.occludedKnownError(0.5), 0.2f);
  EXPECT_FLOAT_EQ(*score.occludedKnownError(1.0), 0.4f);
  EXPECT_FALSE(score.occludedKnownError(1.5));
}

// A made-up height in a shadow, far off against its sigma, spoils the
// calibration of all cells but not that of the cells that were seen.
TEST(MapScore, CalibratesSigmaOverVisibleCellsApart) {
  ElevationMap map(GridSpec::covering({0, 0, 5, 1}, 1.0));
  io::FloatImage height(1, 5, 0.0f);
  io::ByteImage state(1, 5, 0);
  state(0, 4) = 2;
  const double errors[] = {1.0, -1.0, 1.0, -1.0, 20.0};  // sigma 1 each
  for (int c = 0; c < 5; ++c) map.setKnown(0, c, errors[c], 1.0);
  MapScore score;
  score.add(map, height, state);
  // Four visible ratios of +-1: standard deviation sqrt(4 / 3).
  EXPECT_NEAR(*score.sigmaCalibrationVisible(), std::sqrt(4.0 / 3.0), 1e-12);
  EXPECT_GT(*score.sigmaCalibration(), 8.0);
}

}  // namespace
}  // namespace ambler::terrain
