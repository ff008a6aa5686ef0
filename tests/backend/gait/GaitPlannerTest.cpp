// Rover model, stance constraints, circulating gait and leg recovery
// (cmu-1990 'Planning strategies for the Ambler', 'Single leg walking').
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "core/Region.h"
#include "core/Resources.h"
#include "footfall/FootfallConfig.h"
#include "gait/GaitPlanner.h"
#include "gait/RoverConfig.h"
#include "io/FormatError.h"

namespace ambler::gait {
namespace {

GaitContext context() {
  GaitContext ctx = readRoverConfig(findResource("config/rover.json"));
  ctx.footfall = footfall::readFootfallConfig(findResource("config/footfall.json"));
  return ctx;
}

terrain::ElevationMap flatGround() {
  terrain::ElevationMap map(GridSpec::covering({-12, -12, 12, 30}, 0.1));
  for (int r = 0; r < map.grid().rows; ++r)
    for (int c = 0; c < map.grid().cols; ++c) map.setKnown(r, c, 0.0, 0.01);
  return map;
}

TEST(RoverModel, JointsAndFootAreInverse) {
  const RoverModel m;
  for (int leg = 0; leg < kLegCount; ++leg) {
    const LegJoints q{1.1 - leg, 1.7, 2.1};
    const LegJoints back = m.jointsFor(leg, m.footInBody(leg, q));
    EXPECT_NEAR(std::remainder(back.rotation_rad - q.rotation_rad, 2 * M_PI), 0.0, 1e-12);
    EXPECT_NEAR(back.extension_m, q.extension_m, 1e-12);
    EXPECT_NEAR(back.vertical_m, q.vertical_m, 1e-12);
  }
}

// The slowest joint sets a segment's time; a rotation goes the short way.
TEST(RoverModel, MoveTimesFollowTheJointAndBodySpeeds) {
  RoverModel m;
  m.rotation_speed_rad_s = 0.1, m.extension_speed_m_s = 0.2, m.vertical_speed_m_s = 0.25;
  EXPECT_DOUBLE_EQ(m.legSegmentS({0.0, 1.0, 2.0}, {0.0, 1.6, 2.0}), 3.0);  // 0.6 m / 0.2
  EXPECT_DOUBLE_EQ(m.legSegmentS({0.0, 1.0, 2.0}, {0.0, 1.2, 3.0}), 4.0);  // 1 m / 0.25
  EXPECT_NEAR(m.legSegmentS({3.0, 1.0, 2.0}, {-3.0, 1.0, 2.0}), 10 * (2 * M_PI - 6.0), 1e-9);
  m.body_speed_m_s = 0.05, m.body_accel_m_s2 = 0.01, m.body_turn_speed_rad_s = 0.02;
  // Cruise reached after 0.25 m: 1 m at 0.05 m/s plus 5 s of ramps.
  EXPECT_DOUBLE_EQ(m.bodyMoveS(1.0, 0.0, 0.0), 25.0);
  EXPECT_DOUBLE_EQ(m.bodyMoveS(0.04, 0.0, 0.0), 4.0);  // a triangle: 2 sqrt(0.04 / 0.01)
  EXPECT_DOUBLE_EQ(m.bodyMoveS(0.0, -0.5, 0.0), 0.5 / 0.02 + 2.0);
  EXPECT_DOUBLE_EQ(m.bodyMoveS(0.0, 0.0, -2.0), 8.0);
}

// The report's figures the model is built to: walking width 4.5 m (the
// tread), and a body advance of about 3.9 m at that tread (the reach).
TEST(RoverModel, ConfigurationMatchesTheReportsFigures) {
  const GaitContext ctx = context();
  EXPECT_DOUBLE_EQ(2 * ctx.gait.tread_m, 4.5);
  const double lateral = ctx.gait.tread_m - std::abs(ctx.model.shafts[0].x());
  const double travel = 2 * std::sqrt(std::pow(ctx.model.extension_max_m, 2) - lateral * lateral);
  EXPECT_NEAR(travel, 4.33, 0.01);  // >= the report's 3.9 m maximum body advance
  EXPECT_DOUBLE_EQ(ctx.model.mass_kg, 3180.0);
}

TEST(RoverConfig, BadValuesNameTheFileAndKey) {
  const auto dir = std::filesystem::temp_directory_path() / "ambler_rover_config_test";
  std::filesystem::create_directories(dir);
  auto write = [&](const std::string& text) {
    std::ofstream(dir / "rover.json") << text;
    return dir / "rover.json";
  };
  try {
    readRoverConfig(write(R"({"rover": {"extension_m": [2.0, 1.0]}})"));
    FAIL() << "accepted an empty extension range";
  } catch (const io::FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("extension_m"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("rover.json"), std::string::npos) << e.what();
  }
  EXPECT_THROW(readRoverConfig(write(R"({"gait": {"max_body_advance_m": 5}})")), io::FormatError);
  EXPECT_THROW(readRoverConfig(write(R"({"gait": {"pitch_m": "wide"}})")), io::FormatError);
  EXPECT_THROW(readRoverConfig(write(R"({"rover": )")), io::FormatError);
  std::filesystem::remove_all(dir);
}

TEST(Heading, ArcsAreExact) {
  const BodyPose start{{1, 2}, 0.3, 2.4};
  Heading arc;
  arc.radius_m = 5.0;  // a quarter circle to the left
  const BodyPose end = arc.advance(start, 5.0 * M_PI / 2);
  EXPECT_NEAR((start.toBody(end.xy) - Eigen::Vector2d(-5, 5)).norm(), 0.0, 1e-9);
  EXPECT_NEAR(end.heading_rad, 0.3 + M_PI / 2, 1e-12);
  const BodyPose straight = Heading{}.advance(start, 2.0);
  EXPECT_NEAR((start.toBody(straight.xy) - Eigen::Vector2d(0, 2)).norm(), 0.0, 1e-12);
  Heading turn;
  turn.radius_m = 0.0;
  turn.point_turn_left = false;
  const BodyPose turned = turn.advance(start, 0.5);
  EXPECT_NEAR((turned.xy - start.xy).norm(), 0.0, 1e-12);
  EXPECT_NEAR(turned.heading_rad, 0.3 - 0.5, 1e-12);
}

// How the mission log names a walk's path.
TEST(Heading, IsDescribedWithItsSideAndRadius) {
  EXPECT_EQ(describe(Heading{}), "straight");
  EXPECT_EQ(describe(Heading{10.0}), "on an arc of 10.0 m radius to the left");
  EXPECT_EQ(describe(Heading{-6.0}), "on an arc of 6.0 m radius to the right");
  EXPECT_EQ(describe(Heading{0.0, true}), "turning left in place");
  EXPECT_EQ(describe(Heading{0.0, false}), "turning right in place");
}

TEST(Stance, NominalStanceKeepsEveryConstraint) {
  const GaitContext ctx = context();
  const Stance s = nominalStance({{0, 0}, 0.0, 2.4}, ctx.model, ctx.gait);
  const StanceCheck check = checkStance(s, ctx.model, ctx.gait.csp_margin_m);
  EXPECT_TRUE(check.ok()) << constraintName(check.violated) << " leg " << check.leg;
  // The nearest CSP edge is the support edge without the left front foot:
  // from (-2.25, -0.25) to (2.25, 1.25), y = 0.5 + x / 3, 0.5 / sqrt(10 / 9)
  // from the centre.
  EXPECT_NEAR(check.csp_margin_m, 1.5 / std::sqrt(10.0), 1e-9);
}

// Straight ahead from the nominal stance the centre of gravity meets that
// CSP edge (y = 0.5 + x / 3) after 0.5 m, before the rear left foot (1.25 m
// beside its shaft, 1.25 m behind) reaches full extension at
// sqrt(2.5^2 - 1.25^2) - 1.25 = 0.915 m; without the CSP it goes that far.
TEST(Stance, BodyMoveStopsAtTheFirstConstraint) {
  const GaitContext ctx = context();
  const Stance s = nominalStance({{0, 0}, 0.0, 2.4}, ctx.model, ctx.gait);
  const BodyMoveLimit limit = maxBodyMove(s, Heading{}, ctx.model, 0.0, 3.0, 0.001);
  EXPECT_EQ(limit.stopped_by, Constraint::kConservativeSupport);
  EXPECT_NEAR(limit.u, 0.5, 0.002);
  const BodyMoveLimit no_csp = maxBodyMove(s, Heading{}, ctx.model, -10.0, 3.0, 0.001);
  EXPECT_EQ(no_csp.stopped_by, Constraint::kKinematic);
  EXPECT_EQ(no_csp.leg, 0);
  EXPECT_NEAR(no_csp.u, std::sqrt(2.5 * 2.5 - 1.25 * 1.25) - 1.25, 0.002);
}

TEST(Stance, ConstraintsAreNamed) {
  const GaitContext ctx = context();
  Stance s = nominalStance({{0, 0}, 0.0, 2.4}, ctx.model, ctx.gait);
  Stance close = s;
  close.feet[1] = close.feet[0] + Eigen::Vector3d(0.2, 0.2, 0);
  EXPECT_EQ(checkStance(close, ctx.model, 0.0).violated, Constraint::kLegLeg);
  Stance under = s;
  under.feet[4] = {0.5, 0.2, 0.0};  // under the body
  EXPECT_EQ(checkStance(under, ctx.model, 0.0).violated, Constraint::kLegBody);
  Stance deep = s;
  deep.feet[2].z() = -1.0;  // 3.4 m below the links: beyond the vertical travel
  EXPECT_EQ(checkStance(deep, ctx.model, 0.0).violated, Constraint::kKinematic);
  EXPECT_EQ(checkStance(s, ctx.model, 5.0).violated, Constraint::kConservativeSupport);
}

// Twelve steps on flat, known ground: every leg recovers (circulation),
// every step keeps the CSP margin and the body advances.
TEST(GaitPlanner, CirculatesAllSixLegsOnFlatGround) {
  const GaitContext ctx = context();
  const auto map = flatGround();
  Stance s = nominalStance({{0, 0}, 0.0, 2.4}, ctx.model, ctx.gait);
  std::set<int> recovered;
  for (int step = 0; step < 12; ++step) {
    const StepPlan plan = planStep(s, Heading{}, map, ctx);
    ASSERT_TRUE(plan.ok) << "step " << step << ": " << plan.reason;
    if (plan.leg >= 0) {
      recovered.insert(plan.leg);
      EXPECT_TRUE(plan.recovery.found);
      EXPECT_GE(marginWithout(s, ctx.model, plan.leg), ctx.gait.csp_margin_m);
    }
    EXPECT_GE(plan.min_csp_margin, ctx.gait.csp_margin_m - 1e-9);
    EXPECT_TRUE(checkStance(plan.after, ctx.model, ctx.gait.csp_margin_m).ok());
    s = plan.after;
  }
  EXPECT_EQ(recovered.size(), 6u);
  EXPECT_GT(s.body.xy.y(), 5.0);
  EXPECT_NEAR(s.body.xy.x(), 0.0, 0.05);
}

// The circulating gait staggers the two stacks by half a pitch. A foot set
// down far ahead of the other stack's foremost foot leaves that stack
// trailing, with its rear foot at the end of its reach and no leg able to
// lift (a traverse tuning walk ended so). Here the right stack stands 0.65 m
// back: unchecked, the left stack's next foot would lead it by 1.15 pitches.
TEST(GaitPlanner, SetsNoFootMoreThanAPitchAheadOfTheOtherStack) {
  const GaitContext ctx = context();
  const auto map = flatGround();
  Stance s = nominalStance({{0, 0}, 0.0, 2.4}, ctx.model, ctx.gait);
  double right_front = -INFINITY;
  for (int leg = 0; leg < kLegCount; ++leg)
    if (ctx.model.shaft_of_leg[std::size_t(leg)] == 1) {
      s.feet[std::size_t(leg)].y() -= 0.65;
      right_front = std::max(right_front, s.feet[std::size_t(leg)].y());
    }
  ASSERT_TRUE(checkStance(s, ctx.model, ctx.gait.csp_margin_m).ok());
  // The most any left foot on offer leads the right stack by (straight
  // ahead, body and world axes alike), over the 1x search.
  const auto leftLead = [&](const GaitContext& g) {
    double lead = -INFINITY;
    for (const auto& c : planStep(s, Heading{}, map, g).candidates)
      if (g.model.shaft_of_leg[std::size_t(c.leg)] == 0 && c.search_widen == 1.0)
        lead = std::max(lead, c.foothold.y() - right_front);
    return lead;
  };
  GaitContext unchecked = ctx;
  unchecked.gait.max_stack_lead_pitches = 10;
  EXPECT_GT(leftLead(unchecked), 1.1 * ctx.gait.pitch_m);
  const double lead = leftLead(ctx);
  EXPECT_LE(lead, ctx.gait.max_stack_lead_pitches * ctx.gait.pitch_m);
  EXPECT_GT(lead, 0.5 * ctx.gait.pitch_m);  // still a step forward
}

TEST(GaitPlanner, FollowsAnArcOfGivenRadius) {
  const GaitContext ctx = context();
  const auto map = flatGround();
  Heading arc;
  arc.radius_m = 8.0;
  Stance s = nominalStance({{0, 0}, 0.0, 2.4}, ctx.model, ctx.gait);
  for (int step = 0; step < 10; ++step) {
    const StepPlan plan = planStep(s, arc, map, ctx);
    ASSERT_TRUE(plan.ok) << "step " << step << ": " << plan.reason;
    s = plan.after;
  }
  EXPECT_GT(s.body.heading_rad, 0.3);
  EXPECT_NEAR((s.body.xy - Eigen::Vector2d(-8, 0)).norm(), 8.0, 0.05);  // on the circle
}

TEST(GaitPlanner, TurnsInPlace) {
  const GaitContext ctx = context();
  const auto map = flatGround();
  Heading turn;
  turn.radius_m = 0.0;
  Stance s = nominalStance({{0, 0}, 0.0, 2.4}, ctx.model, ctx.gait);
  for (int step = 0; step < 6; ++step) {
    const StepPlan plan = planStep(s, turn, map, ctx);
    ASSERT_TRUE(plan.ok) << "step " << step << ": " << plan.reason;
    EXPECT_TRUE(checkStance(plan.after, ctx.model, ctx.gait.csp_margin_m).ok());
    s = plan.after;
  }
  EXPECT_GT(s.body.heading_rad, 0.7);  // 40 degrees and more
  EXPECT_LT(s.body.xy.norm(), 0.3);    // without walking off
}

// What the operator is shown of a plan: the chosen leg's cost maps, finite
// at the foothold, and the body's path along the arc.
TEST(GaitPlanner, ShowsTheLegsCostMapsAndTheBodysPath) {
  const GaitContext ctx = context();
  const auto map = flatGround();
  Heading arc;
  arc.radius_m = 8.0;
  const Stance s = moveBody(nominalStance({{0, 0}, 0.0, 2.4}, ctx.model, ctx.gait), arc, 0.3);
  const StepPlan plan = planStep(s, arc, map, ctx);
  ASSERT_TRUE(plan.ok) << plan.reason;
  ASSERT_GE(plan.leg, 0);
  ASSERT_TRUE(plan.leg_costs);
  const auto& composite = plan.leg_costs->composite;
  const auto cell = composite.grid.cellAt(plan.foothold.x(), plan.foothold.y());
  ASSERT_TRUE(cell);
  EXPECT_TRUE(std::isfinite(composite.score(cell->row, cell->col)));
  EXPECT_GT(composite.validCount(), 10);
  ASSERT_GE(plan.body_path.size(), 2u);
  EXPECT_NEAR((plan.body_path.front().xy - plan.after_leg.body.xy).norm(), 0.0, 1e-9);
  EXPECT_NEAR((plan.body_path.back().xy - plan.after.body.xy).norm(), 0.0, 1e-9);
  for (std::size_t i = 1; i < plan.body_path.size(); ++i) {
    EXPECT_LE((plan.body_path[i].xy - plan.body_path[i - 1].xy).norm(),
              ctx.gait.body_step_m + 1e-9);
    // On the circle of radius 8 m about (-8, 0).
    EXPECT_NEAR((plan.body_path[i].xy - Eigen::Vector2d(-8, 0)).norm(), 8.0, 1e-6);
  }
}

// The stance a walk stalled in (traverse seed 2, step 70): the right rear
// foot (leg 4) trails two metres behind the body and cannot lift, because
// without it the right stack's other feet (3 and 5) stand too near the
// centre; only leg 5 may lift, and any foothold ahead leaves it so. The
// planner shuffles leg 5 backward instead, after which leg 4 may lift.
TEST(GaitPlanner, ShufflesAFootBackSoThatATrailingLegMayLift) {
  const GaitContext ctx = context();
  const auto map = flatGround();
  Stance s;
  s.body = {{-0.264, 22.962}, 0.0146, 2.4};
  s.feet = {Eigen::Vector3d(-2.424, 22.254, 0),
            {-2.536, 23.319, 0},
            {-1.950, 24.850, 0},
            {1.758, 23.136, 0},
            {1.873, 21.038, 0},
            {2.168, 22.541, 0}};
  ASSERT_TRUE(checkStance(s, ctx.model, ctx.gait.csp_margin_m).ok());
  ASSERT_EQ(liftableLegs(s, ctx.model, ctx.gait.csp_margin_m), std::vector<int>{5});

  const StepPlan plan = planStep(s, Heading{}, map, ctx);
  ASSERT_TRUE(plan.ok) << plan.reason;
  EXPECT_EQ(plan.leg, 5);
  EXPECT_LT(plan.foothold.y(), s.feet[5].y());  // behind where it stood: no search ahead has it
  EXPECT_TRUE(checkStance(plan.after, ctx.model, ctx.gait.csp_margin_m).ok());
  const auto liftable = liftableLegs(plan.after, ctx.model, ctx.gait.csp_margin_m);
  EXPECT_NE(std::find(liftable.begin(), liftable.end(), 4), liftable.end());

  // And the walk goes on from there: leg 4 recovers within two steps.
  Stance next = plan.after;
  bool recovered = false;
  for (int step = 0; step < 2 && !recovered; ++step) {
    const StepPlan p = planStep(next, Heading{}, map, ctx);
    ASSERT_TRUE(p.ok) << p.reason;
    recovered = p.leg == 4;
    next = p.after;
  }
  EXPECT_TRUE(recovered);
}

// The step from `s`; a foot it sets down keeps the leg separation and the
// execution slack from every other foot.
StepPlan planKeepingSlack(const Stance& s, const terrain::ElevationMap& map, const GaitContext& ctx,
                          int step) {
  const StepPlan plan = planStep(s, Heading{}, map, ctx);
  const double slack = ctx.model.min_leg_separation_m + ctx.gait.execution_slack_m;
  if (plan.leg < 0) return plan;
  for (int j = 0; j < kLegCount; ++j) {
    if (j == plan.leg) continue;
    EXPECT_GE((plan.foothold - s.feet[std::size_t(j)]).head<2>().norm(), slack)
        << "step " << step << ", leg " << plan.leg << " by leg " << j;
  }
  return plan;
}

// From a traverse walk (seed 7): a rock's shadow ahead of foot 3 left leg 4
// footholds about the leg separation from foot 3. Set down at the bare
// separation, a touch-down error of a few millimetres put the feet within
// it, and no step could be planned from there (neither leg may lift).
TEST(GaitPlanner, KeepsSlackBetweenANewFootAndItsNeighbours) {
  const GaitContext ctx = context();
  auto map = flatGround();
  forEachCellIn(map.grid(), Box2{1.5, 8.96, 3.0, 9.8},
                [&](int r, int c) { map.setUnobserved(r, c, terrain::CellState::kShadow); });
  Stance s;
  s.body = {{-0.042, 8.293}, 0.0021, 2.4};
  s.feet = {Eigen::Vector3d(-2.240, 7.558, 0),
            {-2.253, 8.548, 0},
            {-2.054, 9.449, 0},
            {2.058, 8.337, 0},
            {2.272, 6.368, 0},
            {2.260, 7.358, 0}};
  ASSERT_TRUE(checkStance(s, ctx.model, ctx.gait.csp_margin_m).ok());

  for (int step = 0; step < 6; ++step) {
    const StepPlan plan = planKeepingSlack(s, map, ctx, step);
    ASSERT_TRUE(plan.ok) << "step " << step << ": " << plan.reason;
    s = plan.after;
  }
}

// From a rock-field walk (seed 3): foot 4 slipped 5 cm towards foot 3 as it
// was set down, to 0.59 m from it. Both may stay where they are (neither
// moves, so their separation cannot shrink), but every other step must still
// be planned, and the walk goes on until one of them lifts.
TEST(GaitPlanner, WalksOnWhenASlipLeftTwoFeetWithinTheLegSeparation) {
  const GaitContext ctx = context();
  const auto map = flatGround();
  Stance s;
  s.body = {{-0.331, 24.316}, 0.0258, 2.4};
  s.feet = {Eigen::Vector3d(-2.479, 22.994, 0),
            {-2.500, 23.818, 0},
            {-2.370, 22.101, 0},
            {1.967, 25.412, 0},
            {1.835, 25.997, 0},
            {2.001, 24.512, 0}};
  ASSERT_EQ(checkStance(s, ctx.model, 0.0).violated, Constraint::kLegLeg);
  ASSERT_TRUE(checkStance(s, s, ctx.model, ctx.gait.csp_margin_m).ok());

  bool lifted_one_of_them = false;
  for (int step = 0; step < 8 && !lifted_one_of_them; ++step) {
    const StepPlan plan = planKeepingSlack(s, map, ctx, step);
    ASSERT_TRUE(plan.ok) << "step " << step << ": " << plan.reason;
    lifted_one_of_them = plan.leg == 3 || plan.leg == 4;
    s = plan.after;
  }
  EXPECT_TRUE(lifted_one_of_them);
  EXPECT_TRUE(checkStance(s, ctx.model, ctx.gait.csp_margin_m).ok());
}

// At the map's far edge a leg's search region may overlap the map by less
// than half a cell and so hold no cell centre: that leg has no foothold
// there, and planning goes on (it threw, which stopped `walk` with an
// error, and would have ended ambler-gs's session thread). The rover
// creeps up to the edge a centimetre at a time, so that the left rear
// leg's 1 m search square, from 1.25 m + the creep, starts on every side
// of the last cell centres (1.25 m) and of the map's edge (1.3 m).
TEST(GaitPlanner, NoFootholdWhereTheSearchJustMissesTheMapsCells) {
  const GaitContext ctx = context();
  terrain::ElevationMap map(GridSpec::covering({-12, -12, 12, 1.3}, 0.1));
  for (int r = 0; r < map.grid().rows; ++r)
    for (int c = 0; c < map.grid().cols; ++c) map.setKnown(r, c, 0.0, 0.01);
  for (int cm = 0; cm <= 10; ++cm) {
    const Stance s = nominalStance({{0, 0.01 * cm}, 0.0, 2.4}, ctx.model, ctx.gait);
    for (int leg = 0; leg < kLegCount; ++leg) {
      std::optional<footfall::CostMaps> maps;
      EXPECT_NO_THROW(maps = legCostMaps(s, Heading{}, map, ctx, std::nullopt, leg))
          << "creep " << cm << " cm, leg " << leg;
      if (maps) {
        EXPECT_LE(maps->composite.grid.bounds().y_max, 1.3 + 1e-9);
      }
    }
    EXPECT_NO_THROW(planStep(s, Heading{}, map, ctx)) << "creep " << cm << " cm";
  }
}

TEST(GaitPlanner, NeedsKnownGround) {
  const GaitContext ctx = context();
  terrain::ElevationMap unknown(GridSpec::covering({-12, -12, 12, 30}, 0.1));
  Stance s = nominalStance({{0, 0}, 0.0, 2.4}, ctx.model, ctx.gait);
  s = moveBody(s, Heading{}, 0.3);  // so that legs may lift
  const StepPlan plan = planStep(s, Heading{}, unknown, ctx);
  EXPECT_EQ(plan.leg, -1);  // no foothold on unknown ground
}

// A wall too tall to lift over between the start and the goal: the path
// goes around it; a low block is lifted over.
// A foothold 2.95 m below the link plane (the far side of a trench, obstacle
// course seed 6): the touch-down aims below it only down to the leg's 3 m
// limit, so the interlocks do not refuse the step.
TEST(LegRecovery, AimsBelowADeepGoalOnlyAsFarAsTheLegReaches) {
  const GaitContext ctx = context();
  const Stance s = nominalStance({{0, 0}, 0.0, 2.4}, ctx.model, ctx.gait);
  const int leg = 5;
  const Eigen::Vector3d deep(2.25, 1.9, 2.4 - 2.95);
  const RecoveryPlan plan =
      planLegRecovery(ctx.model, s, leg, deep, [](const Eigen::Vector2d&, double) { return -1.0; });
  ASSERT_TRUE(plan.found);
  for (const auto& q : plan.waypoints) EXPECT_TRUE(ctx.model.withinLimits(q)) << q.vertical_m;
  EXPECT_DOUBLE_EQ(plan.waypoints.back().vertical_m, ctx.model.vertical_max_m);
  // Where there is room the aim is the full overshoot below the goal.
  const Eigen::Vector3d level(2.25, 1.9, 0.0);
  const RecoveryPlan usual =
      planLegRecovery(ctx.model, s, leg, level, [](const Eigen::Vector2d&, double) { return 0.0; });
  ASSERT_TRUE(usual.found);
  EXPECT_NEAR(usual.waypoints.back().vertical_m, 2.4 + 0.1, 1e-9);
}

TEST(LegRecovery, GoesAroundWhatItCannotLiftOver) {
  const GaitContext ctx = context();
  const Stance s = nominalStance({{0, 0}, 0.0, 2.4}, ctx.model, ctx.gait);
  const int leg = 5;  // right front, moved further back and out
  const Eigen::Vector3d goal(3.0, -0.8, 0.0);
  auto wall = [](double height) {
    return [height](const Eigen::Vector2d& p, double radius) {
      const bool near = std::abs(p.y() - 0.75) < 0.1 + radius && p.x() > 1.8 - radius;
      return near ? height : 0.0;
    };
  };
  const RecoveryPlan low = planLegRecovery(ctx.model, s, leg, goal, wall(0.8));
  ASSERT_TRUE(low.found);
  EXPECT_GE(low.max_lift_m, 0.8 + ctx.recovery.clearance_m - 1e-9);
  const RecoveryPlan tall = planLegRecovery(ctx.model, s, leg, goal, wall(5.0));
  ASSERT_TRUE(tall.found);
  for (const auto& q : tall.waypoints) {
    const Eigen::Vector2d foot = ctx.model.footInBody(leg, q).head<2>();
    EXPECT_FALSE(std::abs(foot.y() - 0.75) < 0.1 && foot.x() > 1.8) << foot.transpose();
  }
  EXPECT_GT(tall.time_s, low.time_s);
  // The path the operator sees: from the foot, over the wall at the planned
  // lift, down to the goal.
  const auto path = footPath(ctx.model, s, leg, low, goal);
  EXPECT_NEAR((path.front() - s.feet[leg]).norm(), 0.0, 1e-9);
  EXPECT_NEAR((path.back() - goal).norm(), 0.0, 1e-9);
  double top = -INFINITY;
  for (const auto& p : path) top = std::max(top, p.z());
  EXPECT_NEAR(top - s.feet[leg].z(), low.max_lift_m, 0.02);
  // Power against time: making energy dearer never makes the plan use more.
  RecoveryOptions thrifty = ctx.recovery;
  thrifty.power_time_ratio = 20.0;
  EXPECT_LE(planLegRecovery(ctx.model, s, leg, goal, wall(0.8), thrifty).energy_j,
            low.energy_j + 1e-6);
}

TEST(GaitPlanner, ReanchorsOnASlightlyDifferentStance) {
  const GaitContext ctx = context();
  const auto map = flatGround();
  Stance s = moveBody(nominalStance({{0, 0}, 0.0, 2.4}, ctx.model, ctx.gait), Heading{}, 0.3);
  const StepPlan plan = planStep(s, Heading{}, map, ctx);
  ASSERT_TRUE(plan.ok);
  ASSERT_GE(plan.leg, 0);
  Stance actual = s;
  actual.body.xy += Eigen::Vector2d(0.02, -0.01);
  const auto moved = reanchorStep(plan, s, actual, Heading{}, ctx);
  ASSERT_TRUE(moved.has_value());
  EXPECT_NEAR((moved->foothold - plan.foothold).head<2>().norm(), std::hypot(0.02, 0.01), 1e-9);
  Stance far = s;
  far.feet[std::size_t((plan.leg + 1) % 6)] += Eigen::Vector3d(0, -3, 0);  // out of reach
  EXPECT_FALSE(reanchorStep(plan, s, far, Heading{}, ctx).has_value());
}

}  // namespace
}  // namespace ambler::gait
