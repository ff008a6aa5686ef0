#include "walk/AutonomousWalk.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <optional>
#include <thread>

#include "core/Resources.h"
#include "footfall/FootfallConfig.h"
#include "gait/DeadReckoning.h"
#include "gait/RoverConfig.h"
#include "sim/RoverWorld.h"
#include "terrain/Locus.h"
#include "terrain/Merge.h"

namespace ambler::walk {

WalkConfig readWalkConfig(const std::filesystem::path& rover_json,
                          const std::filesystem::path& footfall_json,
                          const std::filesystem::path& scanner_json) {
  WalkConfig c;
  c.gait = gait::readRoverConfig(rover_json);
  c.gait.footfall = footfall::readFootfallConfig(footfall_json);
  c.noise = sim::readExecutionNoise(rover_json);
  c.scanner = sim::readScannerModel(scanner_json);
  return c;
}

WalkConfig readDefaultWalkConfig() {
  return readWalkConfig(findResource("config/rover.json"), findResource("config/footfall.json"),
                        findResource("config/rover-scanner.json"));
}

namespace {

// OpenMP threads for the parallel regions this thread starts, restored on
// exit. The rover and the ground station are separate computers: in both
// modes each side's work runs on one core, so a sequential walk cannot borrow
// the rover's core for planning, and a concurrent one does not oversubscribe
// the machine (OpenMP's waiting threads spin on the cores the other side
// needs).
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

// The Perceptron delivers 2 frames a second (cmu-1990).
constexpr double kScanFrameS = 0.5;

// cmu-1990 (fig. 6): walking concurrently, the controller moves the Ambler
// 75 % of the time while perception and the planners are each busy about
// 50 %: execution time is 0.75 of the ground's work.
constexpr double kReportExecutionPerGroundWork = 0.75;

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// A plan and the stance it was made from (the body move is relative to it).
struct Planned {
  gait::Stance from;
  gait::StepPlan plan;
  double ms = 0.0;
};

// What the rover did with one step: reports, and the encoder readings after
// the leg move and after the body move. The truth is kept for scoring only.
struct Executed {
  sim::MoveReport leg, body;
  std::array<sim::LegState, gait::kLegCount> after_leg{}, after_body{};
  Eigen::Vector2d true_before_body{0, 0}, true_after_body{0, 0};
  sensor::RangeImage scan;  // from where the step ended, still in the true pose
  double modelled_s = 0.0;  // execution and the scanner's frame [s]
};

class Walker {
 public:
  Walker(const WalkConfig& config, const WalkOptions& options)
      : cfg_(config),
        opt_(options),
        world_(options.seed, config.gait.model, config.gait.gait, config.noise, config.scanner,
               options.map_extent),
        map_(GridSpec::covering(options.map_extent, options.map_resolution_m)),
        odometry_(config.gait.model, world_.rover().truth()) {}

  WalkResult run();

 private:
  void integrate(const sensor::RangeImage& image);
  Planned plan(const gait::Stance& from);
  Executed execute(const Planned& p, int scan_index);
  void update(const Planned& p, const Executed& e);
  bool diverged(const gait::Stance& predicted) const;

  const WalkConfig& cfg_;
  const WalkOptions& opt_;
  sim::RoverWorld world_;
  terrain::ElevationMap map_;
  gait::KinematicOdometry odometry_;  // what the rover's encoders tell
  WalkResult result_;
};

// LTM builder and merger (cmu-1990): the scan's locus map over the window
// of the local terrain map it can cover, fused into that map.
void Walker::integrate(const sensor::RangeImage& image) {
  const double ground_z = image.sensor_to_world.translation().z() - cfg_.scanner.mount_height;
  const Box2 seen = sim::groundFootprint(cfg_.scanner, image.sensor_to_world, ground_z);
  // The window of the local terrain map under the scan, on its grid.
  const GridSpec& g = map_.grid();
  const int c0 = std::max(0, int(std::floor((seen.x_min - g.origin_x) / g.resolution)));
  const int r0 = std::max(0, int(std::floor((seen.y_min - g.origin_y) / g.resolution)));
  const int c1 = std::min(g.cols, int(std::ceil((seen.x_max - g.origin_x) / g.resolution)));
  const int r1 = std::min(g.rows, int(std::ceil((seen.y_max - g.origin_y) / g.resolution)));
  if (c1 <= c0 || r1 <= r0) return;
  GridSpec window = g;
  window.origin_x = g.origin_x + c0 * g.resolution;
  window.origin_y = g.origin_y + r0 * g.resolution;
  window.cols = c1 - c0;
  window.rows = r1 - r0;
  const auto t0 = Clock::now();
  terrain::mergeInto(map_, terrain::buildLocusMap(image, window));
  result_.ground_busy_s += secondsSince(t0);
}

Planned Walker::plan(const gait::Stance& from) {
  footfall::ScannerView view;
  view.position = from.body.xy;
  view.heading_rad = from.body.heading_rad + M_PI / 2;
  view.horizontal_fov_rad = std::abs(cfg_.scanner.geometry.theta_step) * cfg_.scanner.geometry.cols;
  const auto t0 = Clock::now();
  Planned p{from, gait::planStep(from, opt_.heading, map_, cfg_.gait, view), 0.0};
  p.ms = 1e3 * secondsSince(t0);
  result_.ground_busy_s += p.ms / 1e3;
  return p;
}

// The rover's side of a step: the leg move, the body move and a scan from
// where it ends. The simulator computes them at once; the wall clock then
// waits out the modelled duration (execution plus the scanner's frame time,
// times time_scale), so the ray casting hides inside it like the real
// sensor's acquisition would.
Executed Walker::execute(const Planned& p, int scan_index) {
  const auto t0 = Clock::now();
  Executed e;
  if (p.plan.leg >= 0) e.leg = world_.rover().executeLeg({p.plan.leg, p.plan.recovery.waypoints});
  e.after_leg = world_.rover().legStates();
  e.true_before_body = e.true_after_body = world_.rover().truth().body.xy;
  e.after_body = e.after_leg;
  if (e.leg.completed) {  // else the executive replans before moving the body
    const gait::BodyPose& a = p.plan.after_leg.body;
    const gait::BodyPose& b = p.plan.after.body;
    e.body = world_.rover().executeBody(
        {a.toBody(b.xy), b.heading_rad - a.heading_rad, b.link_z - p.from.body.link_z});
    e.true_after_body = world_.rover().truth().body.xy;
    e.after_body = world_.rover().legStates();
  }
  e.scan = world_.scan(scan_index);
  const double modelled = e.leg.duration_s + e.body.duration_s + kScanFrameS;
  e.modelled_s = modelled;
  if (opt_.time_scale > 0)
    std::this_thread::sleep_until(t0 +
                                  std::chrono::duration_cast<Clock::duration>(
                                      std::chrono::duration<double>(modelled * opt_.time_scale)));
  return e;
}

// Stores the new foothold where the encoders put it, then dead-reckons the
// body from the feet (cmu-1990 'Real-time control').
void Walker::update(const Planned& p, const Executed& e) {
  WalkStep step;
  step.leg = p.plan.leg;
  step.foothold = p.plan.foothold;
  step.body_u = p.plan.body_u;
  step.plan_ms = p.ms;
  step.execute_s = e.leg.duration_s + e.body.duration_s;
  step.csp_margin_m = std::min(e.leg.min_csp_margin_m, e.body.min_csp_margin_m);
  step.event = e.leg.event.empty() ? e.body.event : e.leg.event;
  result_.leg_collisions += e.leg.collisions + e.body.collisions;

  const gait::BodyPose before = odometry_.estimate().body;
  if (p.plan.leg >= 0) odometry_.legMoved(p.plan.leg, e.after_leg[std::size_t(p.plan.leg)].joints);
  const gait::DeadReckoningResult dr = odometry_.bodyMoved(sim::jointsOf(e.after_body));
  step.slipped_feet_detected = int(dr.slipped_legs.size());
  step.dead_reckoning_error_m =
      ((odometry_.estimate().body.xy - before.xy) - (e.true_after_body - e.true_before_body))
          .norm();
  result_.slips_detected += step.slipped_feet_detected;
  result_.dead_reckoning_error_m =
      std::max(result_.dead_reckoning_error_m, step.dead_reckoning_error_m);
  result_.log.push_back(step);
  result_.modelled_execution_s += e.modelled_s;
  ++result_.steps;
}

bool Walker::diverged(const gait::Stance& predicted) const {
  if ((predicted.body.xy - odometry_.estimate().body.xy).norm() > 0.05) return true;
  if (std::abs(predicted.body.heading_rad - odometry_.estimate().body.heading_rad) > 0.02)
    return true;
  for (int i = 0; i < gait::kLegCount; ++i)
    if ((predicted.feet[std::size_t(i)] - odometry_.estimate().feet[std::size_t(i)]).norm() > 0.05)
      return true;
  return false;
}

WalkResult Walker::run() {
  const OmpThreadsInScope one_core(1);  // the ground's; execute() runs on the rover's
  const Eigen::Vector2d start = world_.rover().truth().body.xy;
  sensor::RangeImage first = world_.scan(0);
  first.sensor_to_world = world_.mountPose(odometry_.estimate().body);
  integrate(first);
  Planned next = plan(odometry_.estimate());
  // The walk's wall time runs from the first command sent (set-up and the
  // first scan and plan are the same in both modes).
  const auto t0 = Clock::now();
  std::optional<sensor::RangeImage> pending;  // taken, not yet mapped
  for (int k = 0; k < opt_.steps; ++k) {
    if (!next.plan.ok && pending) {  // planned ahead without the last scan: retry with it
      integrate(*pending);
      pending.reset();
      next = plan(odometry_.estimate());
      ++result_.replans;
    }
    if (!next.plan.ok) {
      result_.stopped = next.plan.reason;
      break;
    }
    const Planned current = std::move(next);
    const bool last = k + 1 == opt_.steps;
    if (opt_.concurrent && !last) {
      // TCA: while the rover executes this step and scans, the previous
      // scan is mapped and the next step planned on the predicted stance.
      // A surprise (unexpected contact, slip, drift) forces a replan.
      auto running = std::async(std::launch::async, [&] {
        const OmpThreadsInScope one_core(1);
        return execute(current, k + 1);
      });
      if (pending) integrate(*pending);
      next = plan(current.plan.after);
      Executed done = running.get();
      update(current, done);
      done.scan.sensor_to_world = world_.mountPose(odometry_.estimate().body);
      pending = std::move(done.scan);
      const bool surprise = !done.leg.event.empty() && done.leg.event != "touch-down";
      const bool drifted = diverged(current.plan.after);
      // A small divergence only needs the interlocks rechecked on the real
      // stance; a surprise or a failed recheck needs a new plan.
      std::optional<gait::StepPlan> kept;
      if (!surprise && drifted && next.plan.ok)
        kept =
            gait::reanchorStep(next.plan, next.from, odometry_.estimate(), opt_.heading, cfg_.gait);
      if (kept) {
        next.plan = std::move(*kept);
        next.from = odometry_.estimate();
        ++result_.rechecked;
      } else if (surprise || drifted) {
        integrate(*pending);
        pending.reset();
        next = plan(odometry_.estimate());
        result_.log.back().replanned = true;
        ++result_.replans;
      }
    } else {
      Executed done = execute(current, k + 1);
      update(current, done);
      if (!last) {  // (only concurrent walks leave a scan pending)
        done.scan.sensor_to_world = world_.mountPose(odometry_.estimate().body);
        integrate(done.scan);
        next = plan(odometry_.estimate());
      }
    }
  }
  std::vector<double> ms;
  for (const auto& s : result_.log) ms.push_back(s.plan_ms);
  if (!ms.empty()) {
    std::nth_element(ms.begin(), ms.begin() + long(ms.size() / 2), ms.end());
    result_.plan_ms_median = ms[ms.size() / 2];
  }
  result_.distance_m = (world_.rover().truth().body.xy - start).norm();
  result_.heading_change_deg =
      world_.rover().truth().body.heading_rad * 180.0 / M_PI;  // started at 0
  result_.dead_reckoning_drift_m =
      (world_.rover().truth().body.xy - odometry_.estimate().body.xy).norm();
  result_.slips = world_.rover().slips();
  result_.trace = world_.rover().trace();
  for (const auto& s : result_.trace) {
    const double margin =
        gait::stabilityMargin(gait::conservativeSupportPolygon(s.feet), s.centre_of_gravity);
    result_.min_stability_margin_m = std::min(result_.min_stability_margin_m, margin);
    if (margin < 0) ++result_.csp_violations;
  }
  result_.wall_s = secondsSince(t0);
  return result_;
}

}  // namespace

WalkResult runWalk(const WalkConfig& config, const WalkOptions& options) {
  return Walker(config, options).run();
}

double timeScaleOfTheReport(const WalkResult& probe) {
  if (!(probe.modelled_execution_s > 0) || !(probe.ground_busy_s > 0)) return 0.0;
  return kReportExecutionPerGroundWork * probe.ground_busy_s / probe.modelled_execution_s;
}

}  // namespace ambler::walk
