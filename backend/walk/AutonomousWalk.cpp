#include "walk/AutonomousWalk.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/Resources.h"
#include "executive/WalkExecutive.h"
#include "gait/RoverConfig.h"
#include "rover/InProcessLink.h"
#include "sim/TerrainFamilies.h"

namespace ambler::walk {

WalkSetup readWalkSetup(const std::filesystem::path& rover_json,
                        const std::filesystem::path& footfall_json,
                        const std::filesystem::path& scanner_json) {
  return {gait::readGaitContext(rover_json, footfall_json),
          rover::readSimulatedRoverConfig(rover_json, scanner_json)};
}

WalkSetup readInstalledWalkSetup() {
  return readWalkSetup(findResource("config/rover.json"), findResource("config/footfall.json"),
                       findResource("config/rover-scanner.json"));
}

namespace {

// OpenMP threads for the parallel regions this thread starts, restored on
// exit. The rover and the ground station are separate computers: the
// ground's work runs on one core in both modes, so a sequential walk cannot
// borrow the rover's core for planning.
class OmpThreadsInScope {
 public:
  explicit OmpThreadsInScope(int threads) : saved_(omp_get_max_threads()) {
    omp_set_num_threads(threads);
  }
  ~OmpThreadsInScope() { omp_set_num_threads(saved_); }
  OmpThreadsInScope(const OmpThreadsInScope&) = delete;
  OmpThreadsInScope& operator=(const OmpThreadsInScope&) = delete;

 private:
  int saved_;
};

using Clock = std::chrono::steady_clock;

// cmu-1990 (fig. 6): walking concurrently, the controller moves the Ambler
// 75 % of the time while perception and the planners are each busy about
// 50 %: execution time is 0.75 of the ground's work.
constexpr double kReportExecutionPerGroundWork = 0.75;

// A fixed key: the batch walk's operator exists only in this process.
link::OperatorKey walkKey() { return {"ambler-cli walk", std::vector<std::uint8_t>(32, 0x5a)}; }

// The truth of the walk, gathered on the rover's thread after each command
// it carried out; read once the link has stopped.
struct TruthTally {
  std::optional<gait::BodyPose> start;
  std::vector<gait::BodyPose> after_body_moves;
  gait::BodyPose now;
  double busy_s = 0.0;
  int collisions = 0;
  int slips = 0;
  std::size_t trace_scored = 0;
  double min_margin_m = INFINITY;
  double min_margin_one_lost_m = INFINITY;
  int violations = 0;

  void observe(const link::Command& command, const rover::SimulatedRover& rover) {
    const auto& world = rover.world().rover();
    if (!start) start = world.truth().body;
    const bool moved =
        rover.modelledBusyS() > busy_s && (std::holds_alternative<link::LegMove>(command.body) ||
                                           std::holds_alternative<link::BodyMove>(command.body));
    busy_s = rover.modelledBusyS();
    now = world.truth().body;
    slips = world.slips();
    if (!moved) return;
    collisions += rover.lastMove().collisions;
    if (std::holds_alternative<link::BodyMove>(command.body)) after_body_moves.push_back(now);
    const auto& trace = world.trace();
    for (; trace_scored < trace.size(); ++trace_scored) {
      const auto& s = trace[trace_scored];
      const double margin =
          gait::stabilityMargin(gait::conservativeSupportPolygon(s.feet), s.centre_of_gravity);
      min_margin_m = std::min(min_margin_m, margin);
      if (margin < 0) ++violations;
      for (std::size_t lost = 0; lost < s.feet.size(); ++lost) {
        std::vector<Eigen::Vector2d> rest = s.feet;
        rest.erase(rest.begin() + long(lost));
        min_margin_one_lost_m =
            std::min(min_margin_one_lost_m,
                     gait::stabilityMargin(gait::supportPolygon(rest), s.centre_of_gravity));
      }
    }
  }
};

// Why the walk cannot go on, or nothing while it can.
std::optional<std::string> stoppedBecause(const executive::WalkExecutive& e,
                                          const executive::ApprovalGate& gate) {
  if (e.phase() == executive::Phase::kDone) return std::string();
  if (e.phase() == executive::Phase::kSuspended)
    return e.events().empty() ? std::string("suspended") : e.events().back().what;
  if (const auto& p = gate.pending(); p && !p->interlocks.passed())
    return "step fails interlock " + p->interlocks.firstFailure();
  return std::nullopt;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
  return v[v.size() / 2];
}

void score(WalkResult& r, const executive::WalkExecutive& e, const TruthTally& truth) {
  const auto& steps = e.stepLog();
  r.steps = e.stepsDone();
  std::vector<double> plan_ms;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const auto& s = steps[k];
    WalkStep w{.leg = s.leg,
               .foothold = s.foothold,
               .body_u = s.body_u,
               .plan_ms = s.plan_ms,
               .planned_ahead = s.planned_ahead,
               .event = s.event,
               .reason = s.reason};
    if (k < truth.after_body_moves.size()) {
      const gait::BodyPose& t = truth.after_body_moves[k];
      const gait::BodyPose& estimate = s.registered.value_or(s.estimated);
      const Eigen::Vector2d along(std::cos(t.heading_rad), std::sin(t.heading_rad));
      const Eigen::Vector2d left(-along.y(), along.x());
      const Eigen::Vector2d error = estimate.xy - t.xy, drift = s.reported.xy - t.xy;
      w.pose_error_m = error.norm();
      w.pose_error_along_m = error.dot(along);
      w.pose_error_across_m = error.dot(left);
      w.dead_reckoning_error_m = drift.norm();
      w.dead_reckoning_error_along_m = drift.dot(along);
      w.dead_reckoning_error_across_m = drift.dot(left);
      w.heading_error_rad = std::remainder(estimate.heading_rad - t.heading_rad, 2 * M_PI);
      w.dead_reckoning_heading_error_rad =
          std::remainder(s.reported.heading_rad - t.heading_rad, 2 * M_PI);
    }
    r.pose_error_max_m = std::max(r.pose_error_max_m, w.pose_error_m);
    r.dead_reckoning_error_max_m = std::max(r.dead_reckoning_error_max_m, w.dead_reckoning_error_m);
    if (s.replanned) ++r.replans;
    plan_ms.push_back(s.plan_ms);
    r.log.push_back(std::move(w));
  }
  if (!r.log.empty()) {
    r.pose_error_final_m = r.log.back().pose_error_m;
    r.dead_reckoning_error_final_m = r.log.back().dead_reckoning_error_m;
    const auto rms = [&r](double WalkStep::*error) {
      double sum = 0.0;
      for (const auto& w : r.log) sum += (w.*error) * (w.*error);
      return std::sqrt(sum / double(r.log.size()));
    };
    r.pose_error_rms_m = rms(&WalkStep::pose_error_m);
    r.heading_error_rms_rad = rms(&WalkStep::heading_error_rad);
    r.dead_reckoning_error_rms_m = rms(&WalkStep::dead_reckoning_error_m);
    r.dead_reckoning_heading_error_rms_rad = rms(&WalkStep::dead_reckoning_heading_error_rad);
  }
  for (const auto& m : e.scanMatches())
    ++(m.accepted ? r.scans_registered : r.scans_not_registered);
  r.plan_ms_median = median(plan_ms);
  if (truth.start) r.distance_m = (truth.now.xy - truth.start->xy).norm();
  r.heading_change_deg = truth.now.heading_rad * 180.0 / M_PI;  // started at 0
  r.min_stability_margin_m = truth.min_margin_m;
  r.min_margin_one_foot_lost_m = truth.min_margin_one_lost_m;
  r.csp_violations = truth.violations;
  r.leg_collisions = truth.collisions;
  r.slips = truth.slips;
  r.modelled_execution_s = truth.busy_s;
  r.ground_work = e.groundWork();
}

}  // namespace

WalkResult runWalk(const WalkSetup& setup, const WalkOptions& options) {
  const OmpThreadsInScope one_core(1);  // the ground's
  std::mutex truth_mutex;
  TruthTally truth;
  rover::SimulatedRoverOptions rover_options;
  rover_options.course = options.course;
  rover_options.terrain = options.terrain;
  rover_options.operators = {walkKey()};
  rover_options.scanned_area = options.map_extent;
  rover_options.time_scale = options.time_scale;
  rover::InProcessLink link(setup.rover, rover_options, std::chrono::milliseconds(1000),
                            [&](const link::Command& c, const rover::SimulatedRover& r) {
                              const std::lock_guard lock(truth_mutex);
                              truth.observe(c, r);
                            });
  link::CommandSigner signer(walkKey());
  executive::ApprovalGate gate;
  gate.setMode(executive::ApprovalMode::kAutoApprove);
  executive::ExecutiveOptions exec_options;
  exec_options.steps = options.steps;
  exec_options.heading = options.heading;
  exec_options.plan_ahead = options.concurrent;
  exec_options.map_extent = options.map_extent;
  exec_options.map_resolution_m = options.map_resolution_m;
  exec_options.register_scans = options.register_scans;
  executive::WalkExecutive executive(link, signer, gate, setup.ground, exec_options);

  const auto t0 = Clock::now();
  auto now_s = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  executive.start(now_s());
  std::optional<std::string> stopped;
  while (!(stopped = stoppedBecause(executive, gate)))
    executive.poll(now_s(), std::chrono::milliseconds(20));
  WalkResult result;
  result.wall_s = now_s();
  result.stopped = *stopped;
  const std::lock_guard lock(truth_mutex);
  score(result, executive, truth);
  return result;
}

WalkOptions onLongTraverse(std::uint64_t seed, int steps) {
  WalkOptions o;
  o.course = sim::longTraverse(seed);
  o.steps = steps;
  o.map_extent = {-10.0, -8.0, 10.0, o.course.extent.y_max - 5.0};
  return o;
}

WalkOptions onCourse(std::string_view course, std::uint64_t seed, int steps) {
  if (course == "traverse") return onLongTraverse(seed, steps);
  WalkOptions o;
  o.course.seed = seed;
  o.steps = steps;
  if (course == "obstacle") return o;
  // The rock fields at the top of the abundance the issue asks a walk to
  // cross; the crater fields as their family draws them. Both as long as
  // the traverse, and mapped as far, so that walks of 100 steps and more
  // end on the field, not at the map's far edge.
  const WalkOptions traverse = onLongTraverse(seed, steps);
  const Box2& field = traverse.course.extent;
  o.map_extent = traverse.map_extent;
  if (course == "rocks20")
    o.terrain = sim::makeRockField({.seed = seed, .extent = field, .abundance = 0.2});
  else if (course == "craters")
    o.terrain = sim::makeFamilyTerrain(sim::TerrainFamily::kCraterField, seed, field);
  else
    throw std::invalid_argument("no walk course '" + std::string(course) +
                                "': obstacle, traverse, rocks20 or craters");
  return o;
}

double timeScaleOfTheReport(const WalkResult& probe) {
  if (!(probe.modelled_execution_s > 0) || !(probe.ground_work.total_s() > 0)) return 0.0;
  return kReportExecutionPerGroundWork * probe.ground_work.total_s() / probe.modelled_execution_s;
}

}  // namespace ambler::walk
