#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <functional>
#include <optional>

#include "InstalledConfig.h"
#include "core/Region.h"
#include "executive/Interlocks.h"
#include "executive/WalkExecutive.h"
#include "rover/InProcessLink.h"
#include "rover/SimulatedRover.h"
#include "terrain/Queries.h"

namespace ambler::executive {
namespace {

using namespace std::chrono_literals;

using testing_config::ground;
using testing_config::simulator;

link::OperatorKey alice() { return {"alice", std::vector<std::uint8_t>(32, 7)}; }
link::OperatorKey bob() { return {"bob", std::vector<std::uint8_t>(32, 8)}; }

// The in-process simulator, counting what the console sends.
class CountingLink : public link::Link {
 public:
  explicit CountingLink(const rover::SimulatedRoverConfig& rover = simulator())
      : inner_(rover, options(), 200ms,
               [this](const link::Command&, const rover::SimulatedRover& r) {
                 move_s = r.lastMove().duration_s;
               }) {}
  void send(const link::Command& c) override {
    if (!std::holds_alternative<link::GroundHeartbeat>(c.body))
      sent.push_back(link::typeName(c.body));
    if (std::holds_alternative<link::Resume>(c.body) && resumes_lost++ < lose_resumes) return;
    if (link::typeName(c.body) == lose_states_from) lose_states = true;
    if (const auto* m = std::get_if<link::LegMove>(&c.body)) {
      sunk_m[std::size_t(m->leg)] = sink_next_leg_m;
      if (!keep_sinking) sink_next_leg_m = 0.0;
    }
    if (const auto* m = std::get_if<link::LegMove>(&c.body); m && joints[std::size_t(m->leg)]) {
      const gait::LegJoints& at = *joints[std::size_t(m->leg)];
      const gait::LegJoints& lift = m->waypoints.front();
      lift_drift_rad = std::max(lift_drift_rad, std::abs(lift.rotation_rad - at.rotation_rad));
      lift_drift_m = std::max(lift_drift_m, std::abs(lift.extension_m - at.extension_m));
    }
    inner_.send(c);
  }
  std::vector<link::Telemetry> receive(std::chrono::milliseconds t) override {
    auto in = inner_.receive(t);
    for (auto& m : in)
      if (auto* leg = std::get_if<link::LegState>(&m.body)) {
        leg->joints.vertical_m += sunk_m[std::size_t(leg->leg)];
        joints[std::size_t(leg->leg)] = leg->joints;
      }
    std::erase_if(in, [&](const link::Telemetry& m) {
      return (std::holds_alternative<sensor::RangeImage>(m.body) && images_lost++ < lose_images) ||
             (lose_states && (std::holds_alternative<link::LegState>(m.body) ||
                              std::holds_alternative<link::BodyState>(m.body)));
    });
    return in;
  }
  std::string describe() const override { return inner_.describe(); }
  int count(const std::string& type) const {
    return int(std::count(sent.begin(), sent.end(), type));
  }
  std::vector<std::string> sent;  // but heartbeats
  // The leg's joints last reported, and how far a lift's first waypoint
  // was from them in rotation and extension.
  std::array<std::optional<gait::LegJoints>, gait::kLegCount> joints{};
  double lift_drift_rad = 0.0, lift_drift_m = 0.0;
  // The next leg set down reports its sole this much lower for as long
  // as it stands: ground that the map put higher.
  double sink_next_leg_m = 0.0;
  bool keep_sinking = false;  // every leg set down, not only the next
  std::array<double, gait::kLegCount> sunk_m{};
  int lose_images = 0;  // the first this many range images never arrive
  int images_lost = 0;
  int lose_resumes = 0;  // the first this many Resumes never reach the rover
  int resumes_lost = 0;
  // From the first command of this type on, no leg or body state arrives.
  std::string lose_states_from;
  bool lose_states = false;
  std::atomic<double> move_s{0.0};  // the simulator's time for the last move it carried out

 private:
  static rover::SimulatedRoverOptions options() {
    rover::SimulatedRoverOptions o;
    o.operators = {alice(), bob()};
    return o;
  }
  rover::InProcessLink inner_;
};

struct Console {
  CountingLink link;
  link::CommandSigner signer{alice()};
  std::vector<missionlog::Decision> decisions;
  ApprovalGate gate{[this](const missionlog::Decision& d) { decisions.push_back(d); }};
  WalkExecutive executive;
  // The executive's clock. The in-process rover answers in real time, so
  // this is real time too: on a slow machine the executive's timeouts and
  // the rover's answers slow down together.
  double now = 0.0;
  const std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();

  explicit Console(ExecutiveOptions o = {}, gait::GaitContext ctx = ground(),
                   const rover::SimulatedRoverConfig& rover = simulator())
      : link(rover), executive(link, signer, gate, std::move(ctx), o) {}

  void pollOnce() {
    now = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    executive.poll(now, 20ms);
  }
  // Polls until `done` or the rover has had `limit_s` to answer.
  template <typename F>
  void pollUntil(F done, double limit_s = 60.0) {
    const double until = now + limit_s;
    while (!done() && now < until) pollOnce();
  }
  bool stopped() const {
    return executive.phase() == Phase::kSuspended || executive.phase() == Phase::kDone;
  }
  // Auto-approved from the start until the walk suspends or ends.
  void walkUntilItStops() {
    gate.setMode(ApprovalMode::kAutoApprove);
    executive.start(now);
    pollUntil([&] { return stopped(); }, 600.0);
  }
  // Another console (`key`) tells the rover to hold; polls until the walk stops.
  void holdFrom(const link::OperatorKey& key) {
    link::CommandSigner other(key);
    link::Command hold;
    hold.rover_id = 1, hold.body = link::Hold{};
    other.sign(hold);
    link.send(hold);
    pollUntil([&] { return executive.phase() == Phase::kSuspended; });
  }
  void untilDecisionNeeded() {
    pollUntil([&] { return executive.phase() == Phase::kAwaitingDecision; });
    ASSERT_EQ(executive.phase(), Phase::kAwaitingDecision);
    ASSERT_TRUE(gate.pending());
  }
};

ExecutiveOptions steps(int n) {
  ExecutiveOptions o;
  o.steps = n;
  return o;
}

TEST(Executive, APlannedStepPassesEveryInterlock) {
  Console c;
  c.executive.start(c.now);
  c.untilDecisionNeeded();
  const auto& report = c.gate.pending()->interlocks;
  EXPECT_TRUE(report.passed()) << report.firstFailure();
  ASSERT_EQ(report.checks.size(), 5u);
  for (const auto& check : report.checks) EXPECT_FALSE(check.detail.empty()) << check.name;
  EXPECT_EQ(c.link.sent, std::vector<std::string>{"AcquireScan"});
}

// `from` with the foot of `leg` pushed straight out from its shaft to
// `beyond` past the leg's reach (a slip), and that outward direction in the
// world.
struct SlippedStance {
  gait::Stance stance;
  Eigen::Vector2d out;
};
SlippedStance slippedOutOfReach(gait::Stance from, int leg, double beyond) {
  const auto& model = ground().model;
  const std::size_t k = std::size_t(leg);
  const Eigen::Vector2d in_body = from.body.toBody(Eigen::Vector2d(from.feet[k].head<2>()));
  const Eigen::Vector2d out = (in_body - model.shaftOf(leg)).normalized();
  const Eigen::Vector2d at = model.shaftOf(leg) + (model.extension_max_m + beyond) * out;
  from.feet[k].head<2>() = from.body.toWorld(at);
  return {from, from.body.rotation() * out};
}

// A supporting foot reported 5 mm beyond the leg's reach (a slip) fails
// any step that places another foot, but a body move that brings it back
// within reach passes: nothing is placed before the body moves.
TEST(Executive, ABodyMoveMayTakeAStanceBackWithinTheLegsReach) {
  Console c;
  c.executive.start(c.now);
  c.untilDecisionNeeded();
  const StepProposal& planned = *c.gate.pending();
  const auto [from, out] = slippedOutOfReach(planned.from, 1, 0.005);

  // Another leg lifted and set down where it stood.
  gait::StepPlan leg_move = planned.plan;
  leg_move.leg = 4;
  leg_move.foothold = from.feet[4];
  leg_move.after_leg = leg_move.after = from;
  leg_move.body_path = {from.body};
  const auto refused = makeProposal(1, from, leg_move, c.executive.map(), ground());
  ASSERT_EQ(refused.interlocks.checks[3].name, "stability");
  EXPECT_NE(refused.interlocks.checks[3].detail.find("kinematic limits after the foot is placed"),
            std::string::npos)
      << refused.interlocks.checks[3].detail;

  gait::StepPlan body_move = planned.plan;
  body_move.leg = -1;
  body_move.after_leg = from;
  body_move.after = from;
  body_move.after.body.xy += 0.02 * out;
  body_move.body_path = {from.body, body_move.after.body};
  const auto passed = makeProposal(2, from, body_move, c.executive.map(), ground());
  const auto& stability = passed.interlocks.checks[3];
  ASSERT_EQ(stability.name, "stability");
  EXPECT_TRUE(stability.passed) << stability.detail;
}

// A fault in the ground's own work (here the footfall module refusing its
// options once a leg may lift, after the first body move) holds the rover
// and suspends the walk, naming the fault, instead of leaving poll() as an
// exception that would end ambler-gs's session thread.
TEST(Executive, AGroundSoftwareFaultHoldsTheRoverAndSuspendsTheWalk) {
  gait::GaitContext ctx = ground();
  ctx.footfall.foot.sigma_margin = NAN;
  Console c(steps(3), ctx);
  c.gate.setMode(ApprovalMode::kAutoApprove);
  c.executive.start(c.now);
  EXPECT_NO_THROW(c.pollUntil([&] { return c.executive.phase() == Phase::kSuspended; }));
  ASSERT_EQ(c.executive.phase(), Phase::kSuspended);
  EXPECT_NE(c.executive.suspendedBecause().find("Hold sent"), std::string::npos)
      << c.executive.suspendedBecause();
  for (const char* named : {"ground software fault: ", "sigma_margin"})
    EXPECT_NE(c.executive.suspendedBecause().find(named), std::string::npos)
        << c.executive.suspendedBecause();
  EXPECT_FALSE(c.gate.pending());
}

// The rover reports a stance whose centre of gravity is 1 cm inside the
// CSP margin (where a slip may leave it): no leg may lift, and a body move
// back out of the margin passes the stability interlock; one that goes on
// into it does not.
TEST(Executive, ABodyMoveMayTakeTheCentreOfGravityBackOutOfTheMargin) {
  Console c;
  c.executive.start(c.now);
  c.untilDecisionNeeded();
  const gait::GaitContext ctx = ground();
  const double limit = ctx.gait.csp_margin_m;
  gait::Stance from = c.gate.pending()->from;
  const Eigen::Vector2d start = from.body.xy;
  for (int i = 0; i < 2000 && gait::marginWithout(from, ctx.model, -1) > limit - 0.01; ++i)
    from.body.xy.x() += 0.001;
  ASSERT_NEAR(gait::marginWithout(from, ctx.model, -1), limit - 0.01, 0.002);

  const auto bodyMoveTo = [&](const Eigen::Vector2d& xy) {
    gait::StepPlan plan = c.gate.pending()->plan;
    plan.leg = -1;
    plan.after_leg = plan.after = from;
    plan.after.body.xy = xy;
    plan.body_path = {from.body, plan.after.body};
    return makeProposal(1, from, plan, c.executive.map(), ctx).interlocks.checks[3];
  };
  const auto back = bodyMoveTo(start);
  ASSERT_EQ(back.name, "stability");
  EXPECT_TRUE(back.passed) << back.detail;
  const auto on = bodyMoveTo(from.body.xy + Eigen::Vector2d(0.01, 0.0));
  EXPECT_FALSE(on.passed) << on.detail;
  EXPECT_NE(on.detail.find("after the body move"), std::string::npos) << on.detail;
}

// A foot reported 6 cm beyond its leg's reach: a body move toward it, which
// leaves it 4 cm beyond, passes, one away from it does not. With any one
// foot 15 cm beyond, whatever the planner proposes passes too (mostly body
// shifts to free a leg). When planner and interlock held different rules,
// the interlock refused the shift for leg 3, and auto-approve held such
// steps for an operator.
TEST(Executive, TheWayBackFromASlipOutOfReachPassesTheStabilityInterlock) {
  Console c;
  c.executive.start(c.now);
  c.untilDecisionNeeded();
  const StepProposal& planned = *c.gate.pending();
  const auto& ctx = ground();
  const auto& model = ctx.model;
  const auto [from, out] = slippedOutOfReach(planned.from, 1, 0.06);
  gait::StepPlan toward = planned.plan;
  toward.leg = -1;
  toward.after_leg = toward.after = from;
  toward.after.body.xy += 0.02 * out;
  toward.body_path = {from.body, toward.after.body};
  ASSERT_GT(model.beyondLimits(toward.after.joints(model, 1)), 0.03);
  const auto closer = makeProposal(1, from, toward, c.executive.map(), ctx);
  EXPECT_TRUE(closer.interlocks.checks[3].passed) << closer.interlocks.checks[3].detail;
  gait::StepPlan away = toward;
  away.after.body.xy = from.body.xy - 0.02 * out;
  away.body_path = {from.body, away.after.body};
  const auto farther = makeProposal(2, from, away, c.executive.map(), ctx);
  EXPECT_FALSE(farther.interlocks.checks[3].passed);
  EXPECT_NE(farther.interlocks.checks[3].detail.find("kinematic limits after the body move"),
            std::string::npos)
      << farther.interlocks.checks[3].detail;

  int plans = 0;
  for (int leg = 0; leg < gait::kLegCount; ++leg) {
    const gait::Stance s = slippedOutOfReach(planned.from, leg, 0.15).stance;
    const gait::StepPlan plan = gait::planStep(s, gait::Heading{}, c.executive.map(), ctx);
    if (!plan.ok) continue;
    ++plans;
    const auto p = makeProposal(std::uint64_t(3 + leg), s, plan, c.executive.map(), ctx);
    EXPECT_TRUE(p.interlocks.checks[3].passed)
        << "leg " << leg << " (" << plan.reason << "): " << p.interlocks.checks[3].detail;
  }
  EXPECT_GE(plans, 3);
}

// Two feet a slip left 1 cm within the leg separation stay where they are
// while another foot is placed: that passes. Setting a foot down within the
// separation of another fails.
TEST(Executive, FeetASlipLeftTooCloseMayStandButNoFootIsPlacedTooClose) {
  Console c;
  c.executive.start(c.now);
  c.untilDecisionNeeded();
  const StepProposal& planned = *c.gate.pending();
  const auto& model = ground().model;
  gait::Stance from = planned.plan.after;  // where a leg may lift
  const auto liftable = gait::liftableLegs(from, model, ground().gait.csp_margin_m);
  ASSERT_FALSE(liftable.empty());
  const int moving = liftable.front();
  const int a = moving < 3 ? 3 : 0, b = a + 1;  // two feet of the other side
  const Eigen::Vector2d apart = (from.feet[std::size_t(a)] - from.feet[std::size_t(b)]).head<2>();
  from.feet[std::size_t(a)].head<2>() = from.feet[std::size_t(b)].head<2>() +
                                        (model.min_leg_separation_m - 0.01) * apart.normalized();
  ASSERT_EQ(gait::checkStance(from, model, 0.0).violated, gait::Constraint::kLegLeg);

  // The moving leg lifted and set down where it stood.
  gait::StepPlan step = planned.plan;
  step.leg = moving;
  step.foothold = from.feet[std::size_t(moving)];
  step.after_leg = step.after = from;
  step.body_path = {from.body};
  const auto stood = makeProposal(1, from, step, c.executive.map(), ground());
  ASSERT_EQ(stood.interlocks.checks[3].name, "stability");
  EXPECT_TRUE(stood.interlocks.checks[3].passed) << stood.interlocks.checks[3].detail;

  // ... or set down 1 cm within the separation of its neighbour.
  const int neighbour = moving % 3 == 0 ? moving + 1 : moving - 1;
  const Eigen::Vector3d& by = from.feet[std::size_t(neighbour)];
  gait::StepPlan crowding = step;
  crowding.foothold.head<2>() = by.head<2>() + (model.min_leg_separation_m - 0.01) *
                                                   (step.foothold - by).head<2>().normalized();
  crowding.after_leg.feet[std::size_t(moving)] = crowding.foothold;
  crowding.after.feet[std::size_t(moving)] = crowding.foothold;
  const auto refused = makeProposal(2, from, crowding, c.executive.map(), ground());
  EXPECT_FALSE(refused.interlocks.checks[3].passed);
  EXPECT_NE(refused.interlocks.checks[3].detail.find("leg-leg after the foot is placed"),
            std::string::npos)
      << refused.interlocks.checks[3].detail;
}

// What the log keeps of a proposal comes back as the replay shows it, with
// a failed interlock's figures; a damaged record is named, not guessed at.
TEST(Executive, AProposalRecordComesBackFromTheLog) {
  StepProposal p;
  p.id = 7;
  p.plan.leg = 3;
  p.plan.foothold = {1.25, -0.5, 0.02};
  p.plan.body_u = 0.41;
  p.plan.min_csp_margin = 0.12;
  p.body_move_m = 0.05;
  p.body_turn_deg = 23.5;
  p.interlocks.checks = {{"plan", true, "body stopped by the CSP"},
                         {"reach", false, "knee 2.1 deg beyond its range"}};
  const auto back = proposalFromRecord(proposalRecord(p));
  EXPECT_EQ(back.id, 7u);
  EXPECT_EQ(back.plan.leg, 3);
  EXPECT_TRUE(back.plan.foothold.isApprox(p.plan.foothold));
  EXPECT_DOUBLE_EQ(back.plan.body_u, 0.41);
  EXPECT_DOUBLE_EQ(back.plan.min_csp_margin, 0.12);
  EXPECT_DOUBLE_EQ(back.body_move_m, 0.05);
  EXPECT_DOUBLE_EQ(back.body_turn_deg, 23.5);
  ASSERT_EQ(back.interlocks.checks.size(), 2u);
  EXPECT_FALSE(back.interlocks.passed());
  EXPECT_EQ(back.interlocks.firstFailure(), p.interlocks.firstFailure());
  for (const std::string bad : {"[]", "{\"proposal\": 7}", "not json",
                                R"({"proposal":1,"leg":0,"body_advance":0,"min_csp_margin_m":0,)"
                                R"("foothold_m":[1,2],"interlocks":[]})"}) {
    EXPECT_THROW(proposalFromRecord(bad), std::invalid_argument) << bad;
  }
  // A log from before the body's move and turn were kept: a straight walk,
  // whose body advance is the move.
  const auto old = proposalFromRecord(
      R"({"proposal":2,"leg":-1,"foothold_m":[0,0,0],"body_advance":0.3,"min_csp_margin_m":0.1,)"
      R"("interlocks":[]})");
  EXPECT_DOUBLE_EQ(old.body_move_m, 0.3);
  EXPECT_DOUBLE_EQ(old.body_turn_deg, 0.0);
}

TEST(Executive, ARejectedStepSendsNothing) {
  Console c;
  c.executive.start(c.now);
  c.untilDecisionNeeded();
  const auto id = c.gate.pending()->id;
  EXPECT_FALSE(c.gate.reject(id, "alice", c.now, "foot too near the box").refused());
  c.pollUntil([&] { return c.executive.phase() == Phase::kSuspended; });
  EXPECT_EQ(c.executive.phase(), Phase::kSuspended);
  EXPECT_EQ(c.link.count("LegMove") + c.link.count("BodyMove"), 0);
  ASSERT_EQ(c.decisions.size(), 1u);
  EXPECT_EQ(c.decisions[0].verdict, missionlog::Verdict::kRejected);
  EXPECT_EQ(c.decisions[0].operator_id, "alice");
  EXPECT_NE(c.decisions[0].detail.find("foot too near the box"), std::string::npos);
}

TEST(Executive, AnApprovedStepMovesTheRover) {
  Console c(steps(1));
  c.executive.start(c.now);
  c.untilDecisionNeeded();
  const double y0 = c.executive.reported()->body.xy.y();
  const auto plan = c.gate.pending()->plan;
  EXPECT_FALSE(c.gate.approve(c.gate.pending()->id, "alice", c.now).refused());
  c.pollUntil([&] { return c.executive.phase() == Phase::kDone; });
  ASSERT_EQ(c.executive.phase(), Phase::kDone);
  EXPECT_EQ(c.executive.stepsDone(), 1);
  // Forward is +y; the rover goes where the plan said, within execution noise.
  EXPECT_NEAR(c.executive.reported()->body.xy.y() - y0, plan.after.body.xy.y() - y0, 0.05);
  EXPECT_GT(plan.body_u, 0.1);
  EXPECT_EQ(c.link.count("LegMove"), plan.leg >= 0 ? 1 : 0);
  EXPECT_EQ(c.link.count("BodyMove"), 1);
  // The task tree: the walk, its step, and the step's scan, plan, approval
  // and moves, each done, each after the one before.
  const auto& tasks = c.executive.tasks();
  for (const auto& t : tasks.tasks()) {
    EXPECT_EQ(t.status, TaskStatus::kDone) << t.name;
    if (t.after >= 0) {
      EXPECT_LE(tasks.task(t.after).ended_s, t.started_s) << t.name;
    }
  }
}

TEST(Executive, EditingTheFootholdRechecksTheInterlocks) {
  Console c(steps(5));
  c.executive.start(c.now);
  c.untilDecisionNeeded();
  // The first steps may move the body only: approve until a leg moves.
  for (int i = 0; i < 4 && c.gate.pending()->plan.leg < 0; ++i) {
    ASSERT_FALSE(c.gate.approve(c.gate.pending()->id, "alice", c.now).refused());
    c.pollUntil([&] { return c.gate.pending().has_value(); });
    c.untilDecisionNeeded();
  }
  c.decisions.clear();
  const int moves_before = c.link.count("LegMove") + c.link.count("BodyMove");
  const auto id = c.gate.pending()->id;
  ASSERT_GE(c.gate.pending()->plan.leg, 0);
  const Eigen::Vector2d planned = c.gate.pending()->plan.foothold.head<2>();
  // Far outside anything scanned: unknown ground, and out of reach.
  EXPECT_FALSE(c.executive.editFoothold(id, {30.0, 40.0}, "alice", c.now).refused());
  const auto& edited = *c.gate.pending();
  EXPECT_FALSE(edited.interlocks.passed());
  EXPECT_NE(edited.interlocks.firstFailure(), "");
  const auto failed = [&](const std::string& name) {
    for (const auto& check : edited.interlocks.checks)
      if (check.name == name) return !check.passed;
    return false;
  };
  EXPECT_TRUE(failed("foothold terrain"));
  EXPECT_TRUE(failed("reach"));
  EXPECT_NE(c.gate.approve(id, "alice", c.now).why().find("interlock"), std::string::npos);
  c.pollOnce();
  EXPECT_EQ(c.link.count("LegMove") + c.link.count("BodyMove"), moves_before);
  ASSERT_EQ(c.decisions.size(), 1u);
  EXPECT_EQ(c.decisions[0].verdict, missionlog::Verdict::kEdited);
  // Back to the planner's foothold: every interlock passes again.
  EXPECT_FALSE(c.executive.editFoothold(id, planned, "alice", c.now).refused());
  EXPECT_TRUE(c.gate.pending()->interlocks.passed()) << c.gate.pending()->interlocks.firstFailure();
  EXPECT_FALSE(c.gate.approve(id, "alice", c.now).refused());
  c.pollUntil([&] { return c.link.count("LegMove") + c.link.count("BodyMove") > moves_before; });
  EXPECT_GT(c.link.count("LegMove") + c.link.count("BodyMove"), moves_before);
}

// The rover's execution noise but no slipped feet: each step ends where its
// plan predicts, within the re-plan tolerance.
rover::SimulatedRoverConfig withoutSlips() {
  auto rover = simulator();
  rover.noise.slip_probability = 0;
  return rover;
}

// Every leg move counts as stopping short here (the rover sets a foot down
// within millimetres of its foothold): the walk replans twice, each time
// with the ground the foot met in the map, then suspends rather than
// replanning for ever, and resuming tries again.
TEST(Executive, EarlyContactsInARowSuspendTheWalk) {
  ExecutiveOptions o = steps(5);
  o.early_contact_m = 1e-4;
  o.max_early_contacts = 3;
  Console c(o, ground(), withoutSlips());
  c.gate.setMode(ApprovalMode::kAutoApprove);
  c.executive.start(c.now);
  c.pollUntil([&] { return c.executive.phase() == Phase::kSuspended; });
  ASSERT_EQ(c.executive.phase(), Phase::kSuspended);
  EXPECT_NE(c.executive.suspendedBecause().find("early contact 3 times in a row"),
            std::string::npos)
      << c.executive.suspendedBecause();
  EXPECT_EQ(c.link.count("LegMove"), 3);
  EXPECT_EQ(c.executive.stepsDone(), 1);  // the first step moves the body only
  // The map holds the ground each foot stopped on at least as high.
  // A later sole resting lower over an earlier felt height drops it.
  const auto& felt = c.executive.feltGround();
  ASSERT_GE(felt.size(), 1u);
  ASSERT_LE(felt.size(), 3u);
  const auto& map = c.executive.map();
  for (const auto& foot : felt) {
    const auto cell = map.grid().cellAt(foot.x(), foot.y());
    ASSERT_TRUE(cell && map.isKnown(cell->row, cell->col));
    EXPECT_GE(map.elevation(cell->row, cell->col), foot.z() - 1e-6) << foot.transpose();
  }

  c.executive.resume(c.now);
  c.pollUntil([&] { return c.executive.phase() == Phase::kSuspended; });
  EXPECT_EQ(c.link.count("LegMove"), 6);
}

// A foot that goes on down below its foothold (ground the map put higher)
// stands placed: the step is planned again from there, the cell under the
// foot takes the sole's height, and it is no early contact: with one early
// contact allowed the walk still goes on to its last step. (Counted as
// one, it suspended there.)
TEST(Executive, AFootThatGoesOnDownIsPlannedAgainNotCountedAsEarly) {
  ExecutiveOptions o = steps(4);
  o.max_early_contacts = 1;
  Console c(o, ground(), withoutSlips());
  c.link.sink_next_leg_m = 0.12;
  c.gate.setMode(ApprovalMode::kAutoApprove);
  c.executive.start(c.now);
  c.pollUntil([&] { return c.executive.phase() == Phase::kDone; });
  ASSERT_EQ(c.executive.phase(), Phase::kDone) << c.executive.suspendedBecause();
  const auto& events = c.executive.events();
  const auto late = std::count_if(events.begin(), events.end(), [](const ExecutiveEvent& e) {
    return e.what.find("met the ground 0.1") != std::string::npos &&
           e.what.find("below its foothold (late contact): replanning") != std::string::npos;
  });
  EXPECT_EQ(late, 1);
  const auto& felt = c.executive.feltGround();
  ASSERT_EQ(felt.size(), 1u);
  const auto cell = c.executive.map().grid().cellAt(felt[0].x(), felt[0].y());
  ASSERT_TRUE(cell);
  EXPECT_NEAR(c.executive.map().elevation(cell->row, cell->col), felt[0].z(), 1e-6);
}

// A rover whose every foot goes on down below its foothold: each leg
// placed is a late contact and the step is planned again, which the
// proposal's own body move never reaches. Three in a row with no step
// done suspend the walk, naming the leg and the depth, rather than let it
// re-place feet for good.
TEST(Executive, LateContactsInARowSuspendTheWalk) {
  ExecutiveOptions o = steps(6);
  Console c(o, ground(), withoutSlips());
  c.link.sink_next_leg_m = 0.12;
  c.link.keep_sinking = true;
  c.walkUntilItStops();
  ASSERT_EQ(c.executive.phase(), Phase::kSuspended);
  const std::string why = c.executive.suspendedBecause();
  EXPECT_NE(why.find("below its foothold, late contact 3 times in a row: the map puts the "
                     "ground too high"),
            std::string::npos)
      << why;
  EXPECT_EQ(c.link.count("LegMove"), 3);
  // Each sole's height went into the map (one resting lower over an
  // earlier one's centre replaced it).
  const auto& felt = c.executive.feltGround();
  ASSERT_FALSE(felt.empty());
  for (const auto& foot : felt) {
    const auto cell = c.executive.map().grid().cellAt(foot.x(), foot.y());
    ASSERT_TRUE(cell);
    EXPECT_GE(c.executive.map().elevation(cell->row, cell->col), foot.z() - 1e-6);
  }

  c.executive.resume(c.now);  // the count starts again
  c.pollUntil([&] { return c.executive.phase() == Phase::kSuspended; });
  EXPECT_EQ(c.link.count("LegMove"), 6);
}

// Over the last `advance_window` steps the body must advance at least
// `min_window_advance` along the heading, as the rover reports it, or the
// walk suspends rather than propose another step (a foot re-placed back
// and forth, each time with a short body move that a shift undoes). Here
// three steps can never walk 50 m: the walk suspends once the window is
// full, giving what the reports add up to.
TEST(Executive, TooLittleAdvanceOverTheLastStepsSuspendsTheWalk) {
  ExecutiveOptions o = steps(8);
  o.advance_window = 3;
  o.min_window_advance = 50.0;
  Console c(o, ground(), withoutSlips());
  c.walkUntilItStops();
  ASSERT_EQ(c.executive.phase(), Phase::kSuspended);
  const std::string why = c.executive.suspendedBecause();
  const auto at = why.find("the body has advanced ");
  ASSERT_NE(at, std::string::npos) << why;
  EXPECT_NE(why.find(" m in the last 3 steps: no foothold lets it move on"), std::string::npos)
      << why;
  // The window fills with the fourth step done (the first only sets where
  // the count starts).
  const auto& log = c.executive.stepLog();
  ASSERT_EQ(log.size(), 4u);
  double along = 0.0;
  for (std::size_t i = 1; i < log.size(); ++i) {
    const auto& a = log[i - 1].reported;
    along += (log[i].reported.xy - a.xy).dot(a.rotation() * Eigen::Vector2d::UnitY());
  }
  EXPECT_GT(along, 0.3);
  EXPECT_NEAR(std::stod(why.substr(at + 22)), along, 1e-3) << why;

  c.executive.resume(c.now);  // the count starts again
  c.pollUntil([&] { return c.executive.stepsDone() > 4 || c.stopped(); });
  EXPECT_EQ(c.executive.stepsDone(), 5);
}

// A point turn soon needs footholds behind the rover that the scanner has
// not seen, and the planner then re-places feet or shifts the body with
// no advance. With a limit of two such steps in a row, the walk suspends
// on the second such proposal instead of sending it, saying why; no two
// steps in a row went out without the body advancing; and resuming starts
// the count anew.
TEST(Executive, StepsThatNeverAdvanceTheBodySuspendTheWalk) {
  ExecutiveOptions o = steps(40);
  o.heading.radius_m = 0.0;  // turn left in place
  o.max_steps_without_advance = 2;
  Console c(o, ground(), withoutSlips());
  c.walkUntilItStops();
  ASSERT_EQ(c.executive.phase(), Phase::kSuspended);
  EXPECT_NE(c.executive.suspendedBecause().find("the body has not advanced in 1 step and"),
            std::string::npos)
      << c.executive.suspendedBecause();
  EXPECT_NE(c.executive.suspendedBecause().find("(turning in place, the inner legs step back"),
            std::string::npos)
      << c.executive.suspendedBecause();
  const auto& log = c.executive.stepLog();
  ASSERT_FALSE(log.empty());
  const double still = ground().gait.body_step_m;
  EXPECT_LT(log.back().body_u, still);
  for (std::size_t i = 1; i < log.size(); ++i)
    EXPECT_FALSE(log[i - 1].body_u < still && log[i].body_u < still)
        << "steps " << i << ", " << i + 1;

  const int done = c.executive.stepsDone();
  c.executive.resume(c.now);
  c.pollUntil([&] { return c.executive.stepsDone() > done || c.stopped(); });
  EXPECT_EQ(c.executive.stepsDone(), done + 1);
}

// Feet set down 8 cm off their footholds stop short of them (early
// contacts) on ground the scans also see: the map fuses the scan's heights
// there, and still holds every felt sole's ground at least as high.
TEST(Executive, TheMapKeepsTheGroundAFootMetAcrossLaterScans) {
  ExecutiveOptions o = steps(6);
  o.max_early_contacts = 100;
  auto rover = withoutSlips();
  rover.noise.placement_m = 0.08;
  Console c(o, ground(), rover);
  c.gate.setMode(ApprovalMode::kAutoApprove);
  c.executive.start(c.now);
  c.pollUntil([&] { return c.executive.stepsDone() == 6; });
  ASSERT_EQ(c.executive.stepsDone(), 6);
  const auto& felt = c.executive.feltGround();
  ASSERT_GE(felt.size(), 3u);
  const auto& map = c.executive.map();
  for (const auto& foot : felt) {
    const auto cell = map.grid().cellAt(foot.x(), foot.y());
    ASSERT_TRUE(cell && map.isKnown(cell->row, cell->col));
    EXPECT_GE(map.elevation(cell->row, cell->col), foot.z() - 1e-6) << foot.transpose();
  }
}

// Steps planned ahead lift from the stance predicted for them; the rover's
// body moves (1 cm errors in the simulator) miss it, and the lift goes
// straight up from where the leg really stands, as its encoders report.
TEST(Executive, ALegLiftsStraightUpFromWhereItStands) {
  Console c(steps(6));
  c.gate.setMode(ApprovalMode::kAutoApprove);
  c.executive.start(c.now);
  c.pollUntil([&] { return c.executive.stepsDone() == 6; });
  ASSERT_EQ(c.executive.stepsDone(), 6);
  ASSERT_GE(c.link.count("LegMove"), 4);
  EXPECT_LT(c.link.lift_drift_rad, 1e-9);
  EXPECT_LT(c.link.lift_drift_m, 1e-9);
}

TEST(Executive, AutoApproveWalksAndStillRunsTheInterlocks) {
  Console c(steps(3), ground(), withoutSlips());
  c.gate.setMode(ApprovalMode::kAutoApprove);
  c.executive.start(c.now);
  c.pollUntil([&] { return c.executive.phase() == Phase::kDone; });
  ASSERT_EQ(c.executive.phase(), Phase::kDone)
      << (c.gate.pending()
              ? c.gate.pending()->interlocks.firstFailure() + " " + describe(*c.gate.pending())
              : "");
  EXPECT_EQ(c.executive.stepsDone(), 3);
  ASSERT_EQ(c.decisions.size(), 3u);
  for (const auto& d : c.decisions) EXPECT_EQ(d.operator_id, kAutoApprover);
  // TCA: steps 2 and 3 were each planned while the step before executed
  // (before its body move was acknowledged) and proposed from that plan.
  EXPECT_EQ(c.executive.stepsPlannedAhead(), 2);
  const auto& tasks = c.executive.tasks();
  int overlapped = 0;
  for (const auto& ahead : tasks.tasks()) {
    if (ahead.name.find("ahead") == std::string::npos) continue;
    const int step = std::stoi(ahead.name.substr(std::string("plan step ").size()));
    for (const auto& t : tasks.tasks())
      if (t.name == "BodyMove" && tasks.task(t.parent).name == "step " + std::to_string(step - 1)) {
        EXPECT_EQ(ahead.status, TaskStatus::kDone);
        EXPECT_LT(ahead.started_s, t.ended_s) << ahead.name;
        ++overlapped;
      }
  }
  EXPECT_EQ(overlapped, 2);

  // A proposal that fails an interlock (here a CSP margin no stance can
  // keep) is not released, even automatically.
  Console d(steps(3));
  d.executive.start(d.now);
  d.untilDecisionNeeded();
  gait::GaitContext strict = ground();
  strict.gait.csp_margin_m = 10.0;
  const StepProposal& planned = *d.gate.pending();
  StepProposal p = makeProposal(planned.id, planned.from, planned.plan, d.executive.map(), strict);
  EXPECT_NE(p.interlocks.firstFailure().find("stability"), std::string::npos);
  d.gate.setMode(ApprovalMode::kAutoApprove);
  d.gate.propose(p, d.now);
  d.pollOnce();
  EXPECT_EQ(d.link.count("LegMove") + d.link.count("BodyMove"), 0);
  EXPECT_EQ(d.executive.phase(), Phase::kAwaitingDecision);
  EXPECT_TRUE(d.gate.pending());
}

// The walk ends with one more scan, registered and merged: the map covers
// where the rover stands and the last step, like every other, carries the
// pose the scan taken after it gave.
TEST(Executive, AWalkClosesWithAScanThatPlacesItsLastStep) {
  Console c(steps(3), ground(), withoutSlips());
  c.gate.setMode(ApprovalMode::kAutoApprove);
  c.executive.start(c.now);
  c.pollUntil([&] { return c.executive.phase() == Phase::kDone; });
  ASSERT_EQ(c.executive.phase(), Phase::kDone);
  EXPECT_EQ(c.link.count("AcquireScan"), 4);
  EXPECT_EQ(c.executive.scanMatches().size(), 4u);
  const auto& tasks = c.executive.tasks().tasks();
  const auto closing = std::find_if(tasks.begin(), tasks.end(),
                                    [](const Task& t) { return t.name == "closing scan"; });
  ASSERT_NE(closing, tasks.end());
  EXPECT_EQ(closing->status, TaskStatus::kDone);
  const auto& log = c.executive.stepLog();
  ASSERT_EQ(log.size(), 3u);
  for (const auto& step : log) {
    ASSERT_TRUE(step.registered.has_value());
    // Each step says what stopped its body move, as its plan did.
    EXPECT_EQ(step.reason.rfind("body ", 0), 0u) << step.reason;
  }
  const gait::BodyPose placed = c.executive.correction().apply(log.back().reported);
  EXPECT_NEAR((log.back().registered->xy - placed.xy).norm(), 0.0, 1e-12);
  EXPECT_NEAR(log.back().registered->heading_rad, placed.heading_rad, 1e-12);
}

// A supporting foot that slipped 5 cm during the body move leaves the rover
// off its predicted stance: the plan made ahead is dropped and the next step
// planned afresh from what the rover reports.
TEST(Executive, APlanAheadIsDroppedWhenTheRoverEndsOffItsPrediction) {
  auto slipping = withoutSlips();
  slipping.noise.slip_probability = 1.0;
  Console c(steps(3), ground(), slipping);
  c.gate.setMode(ApprovalMode::kAutoApprove);
  c.executive.start(c.now);
  c.pollUntil([&] { return c.executive.phase() == Phase::kDone; });
  ASSERT_EQ(c.executive.phase(), Phase::kDone);
  EXPECT_EQ(c.executive.stepsDone(), 3);
  EXPECT_EQ(c.executive.stepsPlannedAhead(), 0);
}

TEST(Executive, ANackSuspendsTheStepWithTheRoversReason) {
  CountingLink link;
  link::CommandSigner mallory({"mallory", std::vector<std::uint8_t>(32, 9)});
  ApprovalGate gate;
  WalkExecutive executive(link, mallory, gate, ground());
  std::vector<std::string> heard;  // what the event sink passed on, as it happened
  executive.onEvent([&](const ExecutiveEvent& e) { heard.push_back(e.what); });
  executive.start(0.0);
  double now = 0.0;
  for (int i = 0; i < 100 && executive.phase() != Phase::kSuspended; ++i)
    executive.poll(now += 0.05, 20ms);
  ASSERT_EQ(executive.phase(), Phase::kSuspended);
  ASSERT_FALSE(executive.events().empty());
  EXPECT_NE(executive.events().back().what.find("refused scan"), std::string::npos)
      << executive.events().back().what;
  EXPECT_NE(executive.events().back().what.find("mallory"), std::string::npos);
  EXPECT_EQ(executive.suspendedBecause(), executive.events().back().what);
  ASSERT_EQ(heard.size(), executive.events().size());
  EXPECT_EQ(heard.back(), executive.events().back().what);
}

// A rover that takes a move on and then never reports where it left the
// legs would keep the step executing for good: the console holds it after
// the move's modelled time, stretched, plus the ack timeout.
void expectHeldWhenTheOutcomeOfA(const std::string& move) {
  ExecutiveOptions o;
  o.steps = 3;
  o.ack_timeout_s = 1.0;
  o.move_time_factor = 0.1;  // the simulator moves at once; keep the wait short
  Console c(o);
  c.link.lose_states_from = move;
  c.gate.setMode(ApprovalMode::kAutoApprove);
  c.executive.start(c.now);
  const auto& under_way = c.executive.moveUnderWay();
  c.pollUntil([&] { return c.stopped() || (c.link.lose_states && under_way); });
  ASSERT_TRUE(under_way.has_value());  // what the status bar shows meanwhile
  const MoveUnderWay shown = *under_way;
  EXPECT_EQ(shown.type, move);
  EXPECT_GT(shown.modelled_s, 0.0);
  EXPECT_DOUBLE_EQ(shown.due_s - shown.acknowledged_s,
                   0.1 * shown.modelled_s + c.executive.ackTimeoutS());
  c.pollUntil([&] { return c.stopped(); });
  EXPECT_FALSE(under_way.has_value());
  ASSERT_EQ(c.executive.phase(), Phase::kSuspended);
  EXPECT_EQ(c.link.count("Hold"), 1);
  const std::string& why = c.executive.suspendedBecause();
  ASSERT_NE(why.find("did not report the outcome of " + move + " "), std::string::npos) << why;
  EXPECT_EQ(why.find("Hold sent"), 0u) << why;
  // The model's time covers the simulator's (a leg's by lowering to the
  // lowest reach at most), and the console waited that long, stretched,
  // after the ack.
  const double modelled = std::stod(why.substr(why.find("the move takes ") + 15));
  const double limit = std::stod(why.substr(why.find(" within ") + 8));
  EXPECT_NE(why.find(move + " " + std::to_string(shown.sequence) + " within"), std::string::npos)
      << why;
  EXPECT_GE(modelled, 0.995 * c.link.move_s.load()) << why;  // printed to 3 digits
  EXPECT_LE(modelled, c.link.move_s.load() + 3.0 / 0.15) << why;
  EXPECT_NEAR(limit, shown.due_s - shown.acknowledged_s, 0.005 * limit) << why;
  EXPECT_GE(limit, 0.1 * modelled + 1.0 - 0.01 * limit) << why;
}

// A two-step walk on auto-approve over a rover whose moves take their time
// (the simulator with a time scale), polled in wall time.
struct TimedConsole {
  explicit TimedConsole(int walk_steps = 2)
      : executive{link, signer, gate, ground(), steps(walk_steps)} {
    gate.setMode(ApprovalMode::kAutoApprove);
  }
  static rover::SimulatedRoverOptions roverOptions() {
    rover::SimulatedRoverOptions ro;
    ro.operators = {alice()};
    ro.time_scale = 0.2;  // a body move about 2.5 s: longer than a poll mapping a scan
    return ro;
  }
  double now() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  }
  void pollUntil(const std::function<bool()>& done) {
    while (!done() && now() < 120) executive.poll(now(), 20ms);
  }
  bool stopped() const {
    return executive.phase() == Phase::kDone || executive.phase() == Phase::kSuspended;
  }

  rover::InProcessLink link{simulator(), roverOptions(), 200ms};
  link::CommandSigner signer{alice()};
  ApprovalGate gate;
  WalkExecutive executive;
  std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
};

// Such a rover acknowledges each move when it takes it on: the console
// shows it under way until its outcome comes, and walks on without a hold.
TEST(Executive, AMoveThatTakesItsTimeIsUnderWayUntilItsOutcomeComes) {
  TimedConsole c;
  c.executive.start(c.now());
  std::vector<std::uint64_t> seen;  // each move under way, once
  c.pollUntil([&] {
    if (const auto& m = c.executive.moveUnderWay();
        m && (seen.empty() || seen.back() != m->sequence))
      seen.push_back(m->sequence);
    return c.stopped();
  });
  ASSERT_EQ(c.executive.phase(), Phase::kDone) << c.executive.suspendedBecause();
  EXPECT_GE(seen.size(), 2u);  // at least a move a step
  EXPECT_FALSE(c.executive.moveUnderWay().has_value());
}

// A hold stops the next motion, not the move under way, and the rover
// refuses a scan until that move ends. Resumed before then, the walk waits
// for the move's outcome, then scans and walks on.
TEST(Executive, ResumedDuringAMoveTheWalkWaitsForTheMoveToEnd) {
  TimedConsole c(1);
  c.executive.start(c.now());
  const auto& under_way = c.executive.moveUnderWay();
  c.pollUntil([&] { return under_way.has_value() || c.stopped(); });
  ASSERT_TRUE(under_way.has_value()) << c.executive.suspendedBecause();
  const MoveUnderWay held = *under_way;
  c.executive.hold(c.now(), "alice");
  ASSERT_EQ(c.executive.phase(), Phase::kSuspended);
  ASSERT_TRUE(under_way.has_value());  // still shown: the rover carries it on
  EXPECT_EQ(under_way->sequence, held.sequence);
  c.executive.resume(c.now());
  EXPECT_EQ(c.executive.phase(), Phase::kAwaitingMoveEnd);
  EXPECT_NE(c.executive.events().back().what.find("waits for the end of " + held.type + " " +
                                                  std::to_string(held.sequence)),
            std::string::npos)
      << c.executive.events().back().what;
  c.pollUntil([&] { return c.executive.phase() != Phase::kAwaitingMoveEnd; });
  EXPECT_EQ(c.executive.phase(), Phase::kScanning) << c.executive.suspendedBecause();
  EXPECT_FALSE(under_way.has_value());
  c.pollUntil([&] { return c.stopped(); });
  ASSERT_EQ(c.executive.phase(), Phase::kDone) << c.executive.suspendedBecause();
  for (const auto& e : c.executive.events())
    EXPECT_EQ(e.what.find("refused"), std::string::npos) << e.what;
}

// A console waiting for the rover's state (which a rover with a move under
// way reports only at the move's end) keeps sending heartbeats once it
// hears the rover: else the rover would hold for a lost link meanwhile.
TEST(Executive, AConsoleWaitingForTheRoversStateKeepsTheLinkAlive) {
  Console c;
  c.link.lose_states = true;
  c.executive.start(c.now, true);  // its Resume starts the rover's link watch
  const auto& events = c.executive.events();
  c.pollUntil([&] { return !events.empty(); }, 4.0);  // longer than the rover's 3 s link timeout
  EXPECT_EQ(c.executive.phase(), Phase::kConnecting);
  for (const auto& e : events) ADD_FAILURE() << e.what;
}

// Keeps what the rover sends until let through, so that the rover can be
// put in a state before the console hears from it.
class WithheldLink : public link::Link {
 public:
  explicit WithheldLink(link::Link& inner) : inner_(inner) {}
  void send(const link::Command& c) override { inner_.send(c); }
  std::vector<link::Telemetry> receive(std::chrono::milliseconds t) override {
    auto in = inner_.receive(t);
    held_.insert(held_.end(), in.begin(), in.end());
    return withholding ? std::vector<link::Telemetry>{} : std::exchange(held_, {});
  }
  std::string describe() const override { return inner_.describe(); }
  const std::vector<link::Telemetry>& held() const { return held_; }
  bool withholding = true;

 private:
  link::Link& inner_;
  std::vector<link::Telemetry> held_;
};

// Bob hands command authority to Alice while his body move is under way.
// Her console, joining then, hears from the rover that it moves, and waits
// for the move's end before it scans, which the rover would refuse until
// then; then it walks without a refusal.
TEST(Executive, AConsoleJoiningDuringAnotherConsolesMoveScansOnceTheMoveHasEnded) {
  auto ro = TimedConsole::roverOptions();
  ro.operators = {alice(), bob()};
  rover::InProcessLink rover{simulator(), ro, 200ms};
  WithheldLink link{rover};
  link::CommandSigner signer{alice()}, bobs{bob()};
  ApprovalGate gate;
  gate.setMode(ApprovalMode::kAutoApprove);
  WalkExecutive executive{link, signer, gate, ground(), steps(1)};
  const auto started = std::chrono::steady_clock::now();
  auto now = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  };
  auto pollUntil = [&](const std::function<bool()>& done) {
    while (!done() && now() < 120) executive.poll(now(), 20ms);
  };

  link.send(bobs.command(1, link::BodyMove{0.0, 0.2, 0.0, 0.0}));
  link.send(signer.command(1, link::RequestAuthority{}));
  link.send(bobs.command(1, link::HandOver{signer.console()}));
  auto acks = [&] {
    return std::count_if(link.held().begin(), link.held().end(), [](const link::Telemetry& t) {
      const auto* a = std::get_if<link::CommandAck>(&t.body);
      return a && a->accepted;
    });
  };
  while (acks() < 3 && now() < 20) link.receive(20ms);
  ASSERT_EQ(acks(), 3);
  link.withholding = false;

  executive.start(now());
  pollUntil([&] { return executive.phase() != Phase::kConnecting; });
  ASSERT_EQ(executive.phase(), Phase::kAwaitingMoveEnd) << executive.suspendedBecause();
  EXPECT_TRUE(executive.report().moving());
  EXPECT_FALSE(executive.moveUnderWay().has_value());  // not this console's
  EXPECT_EQ(executive.events().back().what,
            "connected: the rover reports a move under way; the scan waits for its end");
  pollUntil([&] { return executive.phase() != Phase::kAwaitingMoveEnd; });
  EXPECT_EQ(executive.phase(), Phase::kScanning) << executive.suspendedBecause();
  EXPECT_FALSE(executive.report().moving());
  pollUntil(
      [&] { return executive.phase() == Phase::kDone || executive.phase() == Phase::kSuspended; });
  ASSERT_EQ(executive.phase(), Phase::kDone) << executive.suspendedBecause();
  for (const auto& e : executive.events())
    EXPECT_EQ(e.what.find("refused"), std::string::npos) << e.what;
}

TEST(Executive, ABodyMoveWhoseOutcomeNeverComesIsHeldAfterItsModelledTime) {
  expectHeldWhenTheOutcomeOfA("BodyMove");
}

TEST(Executive, ALegMoveWhoseOutcomeNeverComesIsHeldAfterItsModelledTime) {
  expectHeldWhenTheOutcomeOfA("LegMove");
}

// A two-step walk on auto-approve over a link that loses the first `lost`
// range images, polled until it reaches `until`.
struct LosingImages : Console {
  LosingImages(int lost, Phase until) : Console(options(), ground(), withoutSlips()) {
    link.lose_images = lost;
    gate.setMode(ApprovalMode::kAutoApprove);
    executive.start(now);
    pollUntil([&] { return executive.phase() == until; });
  }
  static ExecutiveOptions options() {
    ExecutiveOptions o;
    o.steps = 2;
    o.image_timeout_s = 1.0;
    o.scan_attempts = 3;
    return o;
  }
};

TEST(Executive, ARangeImageLostAfterItsAcknowledgementIsAskedForAgain) {
  LosingImages c(2, Phase::kDone);
  ASSERT_EQ(c.executive.phase(), Phase::kDone) << c.executive.events().back().what;
  EXPECT_EQ(c.link.count("AcquireScan"), 3 + 2);
  EXPECT_EQ(c.link.count("Hold"), 0);
  const auto& events = c.executive.events();
  const auto asked = std::count_if(events.begin(), events.end(), [](const ExecutiveEvent& e) {
    return e.what.find("no range image within 1 s") != std::string::npos &&
           e.what.find("asking again") != std::string::npos;
  });
  EXPECT_EQ(asked, 2);
  for (const auto& step : c.executive.stepLog()) EXPECT_TRUE(step.registered.has_value());
}

TEST(Executive, AScanWhoseImageNeverComesSuspendsTheStepNamingIt) {
  LosingImages c(1000, Phase::kSuspended);
  ASSERT_EQ(c.executive.phase(), Phase::kSuspended);
  EXPECT_EQ(c.link.count("AcquireScan"), 3);
  EXPECT_EQ(c.link.count("Hold"), 0);  // the rover stands; nothing is under way
  EXPECT_EQ(c.executive.stepsDone(), 0);
  const std::string& why = c.executive.suspendedBecause();
  EXPECT_NE(why.find("no range image within 1 s"), std::string::npos) << why;
  EXPECT_NE(why.find("3 scans asked for"), std::string::npos) << why;
}

// A rover that never answers.
// Reports the rover's state once, then answers nothing.
class SilentLink : public link::Link {
 public:
  void send(const link::Command& c) override { sent.push_back(link::typeName(c.body)); }
  std::vector<link::Telemetry> receive(std::chrono::milliseconds) override {
    if (!stated_) return {};
    stated_ = false;
    auto o = rover::SimulatedRoverOptions();
    return rover::SimulatedRover(simulator(), o).state(0.0);
  }
  std::string describe() const override { return "silence"; }
  std::vector<std::string> sent;

 private:
  bool stated_ = true;
};

TEST(Executive, WaitsForTheRoversStateThenSendsHoldWhenACommandGoesUnanswered) {
  SilentLink link;
  link::CommandSigner signer(alice());
  ApprovalGate gate;
  ExecutiveOptions o;
  o.ack_timeout_s = 2.0;
  WalkExecutive executive(link, signer, gate, ground(), o);
  executive.start(0.0);
  EXPECT_EQ(executive.phase(), Phase::kConnecting);
  EXPECT_TRUE(link.sent.empty());  // nothing before the rover is heard
  executive.poll(1.0, 0ms);
  EXPECT_EQ(executive.phase(), Phase::kScanning);
  executive.poll(2.5, 0ms);
  EXPECT_EQ(executive.phase(), Phase::kScanning);
  executive.poll(3.5, 0ms);
  EXPECT_EQ(executive.phase(), Phase::kSuspended);
  EXPECT_EQ(link.sent, (std::vector<std::string>{"AcquireScan", "GroundHeartbeat",
                                                 "GroundHeartbeat", "Hold"}));
  EXPECT_NE(executive.events().back().what.find("did not acknowledge the AcquireScan"),
            std::string::npos)
      << executive.events().back().what;
  EXPECT_NE(executive.events().back().what.find("within 2 s"), std::string::npos);
}

// Another console's Hold (or the rover's own, on link loss) stops the step
// and withdraws its proposal; resuming ends the hold and plans afresh.
TEST(Executive, ARoverHoldSuspendsTheStepUntilResumed) {
  Console c(steps(1));
  c.executive.start(c.now);
  c.untilDecisionNeeded();
  const auto stale = c.gate.pending()->id;
  c.holdFrom(bob());
  ASSERT_EQ(c.executive.phase(), Phase::kSuspended);
  EXPECT_EQ(c.executive.roverHolding(), "Hold from bob");
  EXPECT_FALSE(c.gate.pending());
  EXPECT_TRUE(c.gate.approve(stale, "alice", c.now).refused());  // nothing stale to approve

  c.executive.resume(c.now);
  c.untilDecisionNeeded();
  EXPECT_EQ(c.executive.roverHolding(), "");
  EXPECT_FALSE(c.gate.approve(c.gate.pending()->id, "alice", c.now).refused());
  c.pollUntil([&] { return c.executive.phase() == Phase::kDone; });
  EXPECT_EQ(c.executive.phase(), Phase::kDone) << c.executive.events().back().what;
  EXPECT_EQ(c.link.count("Resume"), 1);
}

// A Resume the rover never got (sent before it listened) is never
// acknowledged; the rover's holds after it must still stop the walk.
TEST(Executive, ARoverHoldIsSeenWhenTheResumeBeforeItWasLost) {
  Console c(steps(1));
  c.link.lose_resumes = 1;
  c.executive.start(c.now, true);
  c.untilDecisionNeeded();
  ASSERT_EQ(c.link.resumes_lost, 1);
  c.holdFrom(bob());
  ASSERT_EQ(c.executive.phase(), Phase::kSuspended);
  EXPECT_EQ(c.executive.roverHolding(), "Hold from bob");
  EXPECT_FALSE(c.gate.pending());
}

// A walk that reaches the far edge of its map stops for want of
// footholds, and the reason names the edge, not the ground.
TEST(Executive, AWalkStoppedByTheMapsEdgeSaysSo) {
  ExecutiveOptions o = steps(40);
  o.map_extent = {-10.0, -8.0, 10.0, 6.0};
  Console c(o);
  c.walkUntilItStops();
  ASSERT_EQ(c.executive.phase(), Phase::kSuspended);
  const std::string& why = c.executive.suspendedBecause();
  EXPECT_NE(why.find("no step to propose"), std::string::npos) << why;
  EXPECT_NE(why.find("the map ends"), std::string::npos) << why;
  const double body_y = c.executive.reported()->body.xy.y();
  EXPECT_GT(body_y, 6.0 - 2.8);
  EXPECT_LT(body_y, 6.0);
}

TEST(TaskTree, TasksStartInOrderAndSuspendTogether) {
  TaskTree t;
  const int walk = t.add(-1, TaskKind::kGoal, "walk");
  const int scan = t.add(walk, TaskKind::kQuery, "scan");
  const int plan = t.add(walk, TaskKind::kQuery, "plan", scan);
  EXPECT_FALSE(t.canStart(scan));  // its parent has not started
  t.start(walk, 0.0);
  t.start(scan, 1.0);
  EXPECT_FALSE(t.canStart(plan));
  EXPECT_THROW(t.start(plan, 1.5), std::logic_error);
  t.finish(scan, 2.0);
  t.start(plan, 2.0);
  t.suspend(walk, 3.0, "operator");
  EXPECT_EQ(t.task(plan).status, TaskStatus::kSuspended);
  EXPECT_EQ(t.task(plan).note, "operator");
  EXPECT_EQ(t.task(scan).status, TaskStatus::kDone);
  EXPECT_THROW(t.finish(plan, 4.0), std::logic_error);
  EXPECT_EQ(t.children(walk), (std::vector<int>{scan, plan}));
}

// Ground seen only at a grazing angle keeps its height (for scan matching)
// but is no foothold: the planner looks elsewhere, and the interlock refuses
// a foot set down there, naming the oblique cells.
TEST(Executive, NoFootIsPlannedOrSentOntoGroundSeenOnlyObliquely) {
  const gait::GaitContext ctx = ground();
  terrain::ElevationMap map(GridSpec::covering({-12, -12, 12, 30}, 0.1));
  for (int r = 0; r < map.grid().rows; ++r)
    for (int c = 0; c < map.grid().cols; ++c) map.setKnown(r, c, 0.0, 0.01);
  gait::Stance s = gait::nominalStance({{0, 0}, 0.0, 2.4}, ctx.model, ctx.gait);
  gait::StepPlan plan = gait::planStep(s, gait::Heading{}, map, ctx);
  for (int i = 0; i < 4 && plan.ok && plan.leg < 0; ++i) {
    s = plan.after;
    plan = gait::planStep(s, gait::Heading{}, map, ctx);
  }
  ASSERT_TRUE(plan.ok) << plan.reason;
  ASSERT_GE(plan.leg, 0);
  auto footholdCheck = [&](const gait::StepPlan& p) {
    const auto report = checkInterlocks(p, s, stepCommands(p, s), map, ctx);
    for (const auto& check : report.checks)
      if (check.name == "foothold terrain") return check;
    ADD_FAILURE() << "no foothold terrain check";
    return InterlockCheck{};
  };
  EXPECT_TRUE(footholdCheck(plan).passed) << footholdCheck(plan).detail;

  const Disk around{plan.foothold.head<2>(), 0.6};
  forEachCellIn(map.grid(), around, [&](int r, int c) {
    map.setHeight(r, c, terrain::CellState::kOblique, 0.0, 0.01);
  });
  const auto refused = footholdCheck(plan);
  EXPECT_FALSE(refused.passed);
  EXPECT_NE(refused.detail.find(" oblique"), std::string::npos) << refused.detail;

  const gait::StepPlan elsewhere = gait::planStep(s, gait::Heading{}, map, ctx);
  ASSERT_TRUE(elsewhere.ok) << elsewhere.reason;
  if (elsewhere.leg >= 0) {
    const Disk foot{elsewhere.foothold.head<2>(), 0.5 * ctx.model.foot_diameter_m};
    const auto under = terrain::summarize(map, foot);
    EXPECT_EQ(under.oblique, 0);
    EXPECT_GT(under.known, 0);
    EXPECT_TRUE(footholdCheck(elsewhere).passed) << footholdCheck(elsewhere).detail;
  }
}

}  // namespace
}  // namespace ambler::executive
