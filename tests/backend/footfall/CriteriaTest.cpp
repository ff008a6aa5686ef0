// The five footfall criteria (krotkov1989 §4): ideal scores on a plane,
// agreement with a direct per-footprint computation, and the paper's
// statements about which surface each criterion prefers.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include "footfall/Criteria.h"
#include "footfall/Footprint.h"

namespace ambler::footfall {
namespace {

using terrain::CellState;
using terrain::ElevationMap;

constexpr double kRes = 0.02;  // [m]

// A map at 2 cm over [0, width] x [0, height] with heights z(x, y) and a
// constant sigma.
ElevationMap makeMap(double width, double height, const std::function<double(double, double)>& z,
                     double sigma = 0.0) {
  ElevationMap map(GridSpec::covering({0, 0, width, height}, kRes));
  for (int r = 0; r < map.grid().rows; ++r)
    for (int c = 0; c < map.grid().cols; ++c) {
      const auto p = map.grid().cellCenter(r, c);
      map.setKnown(r, c, z(p.x(), p.y()), sigma);
    }
  return map;
}

FootOptions exact() {
  FootOptions o;
  o.sigma_margin = 0.0;
  return o;
}

// Cells of a 30 cm foot at 2 cm: centres within 7.5 cells of the middle.
int footCells() {
  int n = 0;
  for (int dy = -8; dy <= 8; ++dy)
    for (int dx = -8; dx <= 8; ++dx) n += dx * dx + dy * dy <= 7.5 * 7.5 ? 1 : 0;
  return n;
}

double scoreAtPoint(const ScoreMap& m, double x, double y) {
  const auto cell = m.grid.cellAt(x, y);
  return cell ? m.score(cell->row, cell->col) : NAN;
}

TEST(Criteria, NamesRoundTrip) {
  for (const Criterion c : kAllCriteria) EXPECT_EQ(criterionFromName(criterionName(c)), c);
  EXPECT_FALSE(criterionFromName("flatness"));
  EXPECT_EQ(criterionUnit(Criterion::kFreeVolume), "m^3");
  EXPECT_EQ(criterionUnit(Criterion::kSupportArea), "m");
}

TEST(Criteria, FlatPlaneGivesEveryCriterionItsIdealScore) {
  const auto map = makeMap(1.2, 1.2, [](double, double) { return 0.7; });
  const Box2 region{0.3, 0.3, 0.9, 0.9};
  const auto maps = evaluateAllCriteria(map, region, exact());
  ASSERT_EQ(maps.size(), 5u);
  for (const auto& m : maps) {
    EXPECT_EQ(m.validCount(), m.grid.cellCount()) << m.name;
    for (int i = 0; i < m.score.size(); ++i) EXPECT_NEAR(m.score.data()[i], 0.0, 1e-9) << m.name;
    const auto best = bestFoothold(m);
    ASSERT_TRUE(best.found);
    // All tie: the candidate nearest the region's centre wins.
    EXPECT_NEAR(best.x, 0.6, kRes) << m.name;
    EXPECT_NEAR(best.y, 0.6, kRes) << m.name;
  }
}

// With sigma s and margin k the foot may touch at z + k s and the ground
// may be at z - k s: the criteria see a relief of 2 k s (docs/footfall.md).
TEST(Criteria, UncertaintyWidensTheMarginOnAPlane) {
  const double s = 0.01, k = 2.0;
  const auto map = makeMap(
      1.0, 1.0, [](double, double) { return -0.3; }, s);
  FootOptions o;
  o.sigma_margin = k;
  const auto maps = evaluateAllCriteria(map, {0.4, 0.4, 0.6, 0.6}, o);
  const double n = footCells();
  const double area = n * kRes * kRes;
  const double expected[] = {2 * k * s, k * s, 2 * k * s, 2 * k * s * area, 2 * k * s * area};
  for (int c = 0; c < 5; ++c)
    for (int i = 0; i < maps[c].score.size(); ++i)
      EXPECT_NEAR(maps[c].score.data()[i], expected[c], c == 2 ? 1.01 * o.support_bin_m : 1e-7)
          << maps[c].name;
}

TEST(Criteria, FreeVolumeOfASpikeCountsTheFootsCells) {
  const auto spike = makeMap(1.0, 1.0, [](double x, double y) {
    return std::hypot(x - 0.51, y - 0.51) < 0.005 ? 0.1 : 0.0;
  });
  const auto free =
      evaluateFootfalls(spike, {0.51, 0.51, 0.51, 0.51}, Criterion::kFreeVolume, exact());
  ASSERT_EQ(free.grid.cellCount(), 1);
  // V = (N - 1) * 0.1 m * cell area: every cell but the spike is 0.1 below.
  EXPECT_NEAR(free.score(0, 0), (footCells() - 1) * 0.1 * kRes * kRes, 1e-9);
  EXPECT_EQ(footCells(), 177);
}

// Direct per-footprint evaluation: loops over the disk, sorts for the
// support area, solves the 3 x 3 normal equations for the plane.
struct Direct {
  const ElevationMap& map;
  FootOptions o;

  bool known(int r, int c) const {
    return r >= 0 && c >= 0 && r < map.grid().rows && c < map.grid().cols && map.isKnown(r, c);
  }
  // Known, and so are the cells within the clearance of it.
  bool clear(int r, int c) const {
    const int n = int(std::floor(o.clearance_m / kRes + 1e-9));
    for (int dr = -n; dr <= n; ++dr)
      for (int dc = -n; dc <= n; ++dc)
        if (!known(r + dr, c + dc)) return false;
    return true;
  }

  double at(Criterion criterion, int r0, int c0) const {
    const double radius = o.diameter_m / 2 / kRes, k = o.sigma_margin, a = kRes * kRes;
    std::vector<double> lo;
    double top = -INFINITY, bottom = INFINITY, sum_lo = 0, mx = 0, my = 0, var = 0;
    Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
    Eigen::Vector3d atz = Eigen::Vector3d::Zero();
    for (int dy = -8; dy <= 8; ++dy)
      for (int dx = -8; dx <= 8; ++dx) {
        if (dx * dx + dy * dy > radius * radius) continue;
        const int r = r0 + dy, c = c0 + dx;
        if (!clear(r, c)) return NAN;
        const double z = map.elevation(r, c), s = map.sigma(r, c);
        top = std::max(top, z + k * s), bottom = std::min(bottom, z - k * s);
        lo.push_back(z - k * s), sum_lo += z - k * s, var += s * s;
        mx += dx * kRes * (z - k * s), my += dy * kRes * (z - k * s);
        const Eigen::Vector3d row(dx * kRes, dy * kRes, 1.0);
        ata += row * row.transpose(), atz += row * z;
      }
    const double n = double(lo.size());
    switch (criterion) {
      case Criterion::kMaxMin:
        return top - bottom;
      case Criterion::kPlanarFit: {
        const Eigen::Vector3d p = ata.ldlt().solve(atz);
        double ss = 0;
        for (int dy = -8; dy <= 8; ++dy)
          for (int dx = -8; dx <= 8; ++dx)
            if (dx * dx + dy * dy <= radius * radius) {
              const double e =
                  map.elevation(r0 + dy, c0 + dx) - (p.x() * dx * kRes + p.y() * dy * kRes + p.z());
              ss += e * e;
            }
        const double tilt = std::acos(1 / std::sqrt(1 + p.x() * p.x() + p.y() * p.y()));
        if (tilt * 180 / M_PI > o.max_tilt_deg) return NAN;
        return std::sqrt(ss / n) + k * std::sqrt(var / n);
      }
      case Criterion::kSupportArea: {
        const int kth = int(std::ceil(o.min_support_fraction * n - 1e-9));
        std::sort(lo.begin(), lo.end(), std::greater<>());
        return std::max(top - lo[kth - 1], 0.0);
      }
      case Criterion::kFreeVolume:
        return (n * top - sum_lo) * a;
      case Criterion::kEquilibrium:
        return (n * top - sum_lo) * a +
               o.equilibrium_moment_weight * std::hypot(mx, my) * a / (o.diameter_m / 2);
    }
    return NAN;
  }
};

TEST(Criteria, MatchDirectEvaluationOnRoughGroundWithGaps) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::uniform_real_distribution<double> sigma(0.001, 0.02);
  auto map = makeMap(1.6, 1.4, [&](double x, double y) {
    return 0.2 * std::sin(3 * x) + 0.1 * std::cos(5 * y) + noise(rng);
  });
  for (int r = 0; r < map.grid().rows; ++r)
    for (int c = 0; c < map.grid().cols; ++c) {
      if ((r / 3) % 11 == 5 && (c / 3) % 13 == 7) {  // 3 x 3 shadows every 22 x 26 cm
        map.setUnobserved(r, c, CellState::kShadow);
        continue;
      }
      map.setKnown(r, c, map.elevation(r, c), sigma(rng));
    }
  const Box2 region{0.1, 0.1, 1.5, 1.3};  // reaches the map's border: partial feet are invalid
  for (const double clearance_m : {0.0, kRes}) {
    FootOptions o;
    o.max_tilt_deg = 20;
    o.clearance_m = clearance_m;
    const auto maps = evaluateAllCriteria(map, region, o);
    const Direct direct{map, o};
    int compared = 0;
    for (int ci = 0; ci < 5; ++ci) {
      const auto& m = maps[ci];
      for (int r = 0; r < m.grid.rows; r += 3)
        for (int c = 0; c < m.grid.cols; c += 3) {
          const auto p = m.grid.cellCenter(r, c);
          const auto cell = map.grid().cellAt(p.x(), p.y());
          ASSERT_TRUE(cell);
          const double expected = direct.at(kAllCriteria[ci], cell->row, cell->col);
          const double got = m.score(r, c);
          ASSERT_EQ(std::isnan(expected), std::isnan(got))
              << m.name << " at " << r << "," << c << ", clearance " << clearance_m;
          if (std::isnan(expected)) continue;
          const double tolerance =
              kAllCriteria[ci] == Criterion::kSupportArea ? o.support_bin_m : 1e-5 * (1 + expected);
          EXPECT_NEAR(got, expected, tolerance) << m.name << " at " << r << "," << c;
          ++compared;
        }
    }
    EXPECT_GT(compared, 800) << "clearance " << clearance_m;
  }
}

// krotkov1989 fig. 5a/b: max-min prefers a flat surface punctuated by a
// spike to an undulating one; free volume does not. Left half: flat with a
// 3 cm spike every 10 cm (every foot stands on some); right half: egg-crate
// undulation of 2 cm amplitude.
TEST(Criteria, MaxMinPrefersSpikesToUndulationFreeVolumeDoesNot) {
  const auto map = makeMap(2.0, 1.0, [](double x, double y) {
    if (x < 1.0) {
      const bool spike = std::fmod(x + 1e-9, 0.1) < kRes && std::fmod(y + 1e-9, 0.1) < kRes;
      return spike ? 0.03 : 0.0;
    }
    return 0.02 * std::sin(2 * M_PI * x / 0.4) * std::sin(2 * M_PI * y / 0.4);
  });
  // The best foot on each patch, feet wholly on it.
  const Box2 spikes{0.2, 0.2, 0.8, 0.8}, undulation{1.2, 0.2, 1.8, 0.8};
  auto best = [&](const Box2& box, Criterion c) {
    return bestFoothold(evaluateFootfalls(map, box, c, exact())).score;
  };
  EXPECT_NEAR(best(spikes, Criterion::kMaxMin), 0.03, 1e-6);
  EXPECT_GT(best(undulation, Criterion::kMaxMin), best(spikes, Criterion::kMaxMin) + 0.002);
  EXPECT_GT(best(spikes, Criterion::kFreeVolume), 1.2 * best(undulation, Criterion::kFreeVolume));
}

// krotkov1989 §4: support area cannot tell two sinusoids of the same
// frequency and different amplitude apart; free volume picks the smaller
// amplitude. Ribs of 6 cm wavelength: their crests are a third of the foot,
// more than A_min = 25 %, so the foot is supported without penetrating
// whatever the amplitude (d_opt = 0 on both).
TEST(Criteria, SupportAreaCannotTellAmplitudesApartFreeVolumeCan) {
  auto ribs = [](double amplitude) {
    return [amplitude](double x, double) {
      const int column = int(std::floor(x / kRes));
      return amplitude * std::cos(2 * M_PI * column / 3.0);
    };
  };
  const auto big = ribs(0.05), small = ribs(0.01);
  const auto map =
      makeMap(2.0, 1.0, [&](double x, double y) { return x < 1.0 ? big(x, y) : small(x, y); });
  const Box2 left{0.3, 0.3, 0.7, 0.7}, right{1.3, 0.3, 1.7, 0.7};
  auto bestIn = [&](const Box2& box, Criterion c) {  // feet wholly on one patch
    return bestFoothold(evaluateFootfalls(map, box, c, exact())).score;
  };
  EXPECT_EQ(bestIn(left, Criterion::kSupportArea), bestIn(right, Criterion::kSupportArea));
  EXPECT_EQ(bestIn(left, Criterion::kSupportArea), 0.0);
  EXPECT_GT(bestIn(left, Criterion::kFreeVolume), 4 * bestIn(right, Criterion::kFreeVolume));
}

// krotkov1989 fig. 5d: two 4 cm holes balanced about the foot centre versus
// the same two holes on one side. Free volume sees no difference;
// equilibrium prefers the balanced foot.
TEST(Criteria, EquilibriumPrefersBalancedHoles) {
  auto hole = [](double x, double y, double cx, double cy) {
    return std::abs(x - cx) < 0.03 && std::abs(y - cy) < 0.03;
  };
  const double balanced_x = 0.51, one_side_x = 1.51, y0 = 0.51;
  const auto map = makeMap(2.0, 1.0, [&](double x, double y) {
    const bool in_hole = hole(x, y, balanced_x - 0.08, y0) || hole(x, y, balanced_x + 0.08, y0) ||
                         hole(x, y, one_side_x + 0.04, y0) || hole(x, y, one_side_x + 0.10, y0);
    return in_hole ? -0.04 : 0.0;
  });
  const Box2 region{0.2, 0.2, 1.8, 0.8};
  const auto free = evaluateFootfalls(map, region, Criterion::kFreeVolume, exact());
  const auto eq = evaluateFootfalls(map, region, Criterion::kEquilibrium, exact());
  const double v_balanced = scoreAtPoint(free, balanced_x, y0);
  EXPECT_NEAR(v_balanced, scoreAtPoint(free, one_side_x, y0), 1e-9);
  EXPECT_GT(v_balanced, 0.0);
  // Balanced: E = 0, so equilibrium equals the free volume.
  EXPECT_NEAR(scoreAtPoint(eq, balanced_x, y0), v_balanced, 1e-9);
  // One side: the holes' volume sits 7 cm from the centre, E = 0.07 V.
  EXPECT_NEAR(scoreAtPoint(eq, one_side_x, y0), v_balanced * (1 + 0.07 / 0.15), 1e-7);
}

TEST(Criteria, NeverStandsOnShadowOrUnknownCells) {
  // Flat everywhere, so every foot ties, and the tie-break pulls to the
  // centre, which is in shadow.
  auto map = makeMap(1.2, 1.2, [](double, double) { return 0.0; });
  for (int r = 25; r < 35; ++r)
    for (int c = 25; c < 35; ++c) map.setUnobserved(r, c, CellState::kShadow);
  map.setUnobserved(5, 5, CellState::kUnknown);
  const Box2 region{0.0, 0.0, 1.2, 1.2};
  const double radius = 0.15;
  for (const auto& m : evaluateAllCriteria(map, region, exact())) {
    const auto best = bestFoothold(m);
    ASSERT_TRUE(best.found) << m.name;
    // The foot's disk must clear the shadow square [0.5, 0.7]^2.
    const double dx = std::max({0.5 - best.x, 0.0, best.x - 0.7});
    const double dy = std::max({0.5 - best.y, 0.0, best.y - 0.7});
    EXPECT_GT(std::hypot(dx, dy), radius - kRes) << m.name;
    EXPECT_TRUE(std::isnan(scoreAtPoint(m, 0.6, 0.6))) << m.name;
    EXPECT_TRUE(std::isnan(scoreAtPoint(m, 0.11, 0.11))) << m.name << " covers the unknown cell";
  }
}

// One unseen cell at (30, 30); feet on the same row, their disks (7.5
// cells in radius) 8, 9 and 10 cells away from it along the row.
TEST(Criteria, ClearanceKeepsTheSoleAwayFromUnseenCells) {
  auto map = makeMap(1.2, 1.2, [](double, double) { return 0.0; });
  map.setUnobserved(30, 30, CellState::kShadow);
  const auto centre = [&](int col) { return map.grid().cellCenter(30, col); };
  auto valid = [&](double clearance_m, int col) {
    FootOptions o = exact();
    o.clearance_m = clearance_m;
    const auto p = centre(col);
    const Box2 region{p.x() - kRes / 2, p.y() - kRes / 2, p.x() + kRes / 2, p.y() + kRes / 2};
    const auto m = evaluateFootfalls(map, region, Criterion::kMaxMin, o);
    return std::isfinite(scoreAtPoint(m, p.x(), p.y()));
  };
  EXPECT_FALSE(valid(0.0, 37));  // the sole covers it
  EXPECT_TRUE(valid(0.0, 38));
  EXPECT_FALSE(valid(kRes, 38));  // one cell of clearance
  EXPECT_TRUE(valid(kRes, 39));
  EXPECT_TRUE(valid(0.9 * kRes, 38));  // whole cells only: less than one is none
  EXPECT_FALSE(valid(2 * kRes, 39));
  EXPECT_TRUE(valid(2 * kRes, 40));
  // The map's edge is no clearance either: off the map nobody saw anything.
  EXPECT_TRUE(valid(0.0, 7));  // the sole reaches column 0
  EXPECT_FALSE(valid(kRes, 7));
  EXPECT_TRUE(valid(kRes, 8));
}

TEST(Criteria, UncertainGroundLosesToCertainGround) {
  auto map = makeMap(2.0, 1.0, [](double, double) { return 0.0; });
  for (int r = 0; r < map.grid().rows; ++r)
    for (int c = 0; c < map.grid().cols; ++c)
      map.setKnown(r, c, 0.0, c < map.grid().cols / 2 ? 0.02 : 0.002);
  for (const auto& m : evaluateAllCriteria(map, {0.2, 0.2, 1.8, 0.8})) {
    const auto best = bestFoothold(m);
    ASSERT_TRUE(best.found);
    EXPECT_GT(best.x, 1.15) << m.name;
  }
}

TEST(Criteria, PlanarFitAcceptsTiltUpToTheLimit) {
  auto tilted = [](double deg) {
    return makeMap(1.0, 1.0, [deg](double x, double y) {
      return std::tan(deg * M_PI / 180) * (0.6 * x + 0.8 * y);
    });
  };
  const Box2 region{0.4, 0.4, 0.6, 0.6};
  const auto gentle = evaluateFootfalls(tilted(10), region, Criterion::kPlanarFit, exact());
  EXPECT_EQ(gentle.validCount(), gentle.grid.cellCount());
  EXPECT_NEAR(bestFoothold(gentle).score, 0.0, 1e-7);
  const auto steep = evaluateFootfalls(tilted(20), region, Criterion::kPlanarFit, exact());
  EXPECT_EQ(steep.validCount(), 0);
  const auto slope = planeTilt(tilted(20), region);
  EXPECT_NEAR(slope.score(3, 3), 20.0, 1e-3);
}

TEST(Criteria, RejectsBadOptionsAndRegions) {
  const auto map = makeMap(1.0, 1.0, [](double, double) { return 0.0; });
  FootOptions o;
  o.diameter_m = -1;
  EXPECT_THROW(evaluateFootfalls(map, {0, 0, 1, 1}, Criterion::kMaxMin, o), std::invalid_argument);
  o = {};
  o.min_support_fraction = NAN;
  EXPECT_THROW(evaluateFootfalls(map, {0, 0, 1, 1}, Criterion::kSupportArea, o),
               std::invalid_argument);
  o = {};
  o.clearance_m = NAN;
  EXPECT_THROW(evaluateFootfalls(map, {0, 0, 1, 1}, Criterion::kMaxMin, o), std::invalid_argument);
  EXPECT_THROW(evaluateFootfalls(map, {5, 5, 6, 6}, Criterion::kMaxMin), std::invalid_argument);
  EXPECT_THROW(evaluateFootfalls(map, {0, 0, NAN, 1}, Criterion::kMaxMin), std::invalid_argument);
}

// What a caller checks before asking for candidates: a region on the map
// by less than half a cell holds no cell centre, and candidateCells()
// refuses it.
TEST(Criteria, ARegionHoldsACellCentreOrHasNoCandidates) {
  const GridSpec g = GridSpec::covering({0, 0, 1, 1}, 0.1);  // centres 0.05 ... 0.95
  EXPECT_TRUE(holdsCellCentre(g, {0.0, 0.0, 0.05, 0.05}));
  EXPECT_FALSE(holdsCellCentre(g, {0.96, 0.0, 1.0, 1.0}));
  EXPECT_THROW(candidateCells(g, {0.96, 0.0, 1.0, 1.0}), std::invalid_argument);
  EXPECT_FALSE(holdsCellCentre(g, {2.0, 2.0, 3.0, 3.0}));
  EXPECT_FALSE(holdsCellCentre(g, {0.3, 0.2, 0.1, 0.4}));
  EXPECT_FALSE(holdsCellCentre(g, {0.0, 0.0, NAN, 1.0}));
}

}  // namespace
}  // namespace ambler::footfall
