// ambler-cli walk: a headless autonomous walk across the simulated obstacle
// course (cmu-1990: scan, map, merge, footfall, gait plan, execute), by the
// walk executive ambler-gs runs, auto-approving steps that pass every
// interlock.
#include <cmath>
#include <cstdlib>
#include <memory>

#include "cli/Arguments.h"
#include "cli/Commands.h"
#include "core/Resources.h"
#include "walk/AutonomousWalk.h"

namespace ambler::cli {

namespace {

namespace fs = std::filesystem;

struct WalkArgs {
  int seed = 1;
  int steps = 25;
  std::string course = "obstacle";  // obstacle | traverse
  WalkPath path;
  bool sequential = false;
  bool compare = false;
  bool no_registration = false;
  double time_scale = 0.0;
  bool log = false;
  bool json = true;
  std::string rover_config, footfall_config, scanner_config;
};

nlohmann::json stepJson(const walk::WalkStep& s) {
  nlohmann::json j = {{"leg", s.leg},
                      {"body_u", s.body_u},
                      {"plan_ms", s.plan_ms},
                      {"planned_ahead", s.planned_ahead},
                      {"pose_error_m", s.pose_error_m},
                      {"pose_error_along_m", s.pose_error_along_m},
                      {"pose_error_across_m", s.pose_error_across_m},
                      {"dead_reckoning_error_m", s.dead_reckoning_error_m},
                      {"dead_reckoning_error_along_m", s.dead_reckoning_error_along_m},
                      {"dead_reckoning_error_across_m", s.dead_reckoning_error_across_m},
                      {"heading_error_rad", s.heading_error_rad},
                      {"dead_reckoning_heading_error_rad", s.dead_reckoning_heading_error_rad},
                      {"event", s.event},
                      {"reason", s.reason}};
  if (s.leg >= 0) j["foothold"] = {s.foothold.x(), s.foothold.y(), s.foothold.z()};
  return j;
}

nlohmann::json resultJson(const walk::WalkResult& r, bool concurrent, bool log) {
  nlohmann::json out = {
      {"mode", concurrent ? "concurrent" : "sequential"},
      {"steps", r.steps},
      {"distance_m", r.distance_m},
      {"heading_change_deg", r.heading_change_deg},
      {"min_stability_margin_m", r.min_stability_margin_m},
      {"csp_violations", r.csp_violations},
      {"leg_collisions", r.leg_collisions},
      {"plan_ms_median", r.plan_ms_median},
      {"pose_error_final_m", r.pose_error_final_m},
      {"pose_error_max_m", r.pose_error_max_m},
      {"pose_error_rms_m", r.pose_error_rms_m},
      {"heading_error_rms_rad", r.heading_error_rms_rad},
      {"dead_reckoning_error_final_m", r.dead_reckoning_error_final_m},
      {"dead_reckoning_error_max_m", r.dead_reckoning_error_max_m},
      {"dead_reckoning_error_rms_m", r.dead_reckoning_error_rms_m},
      {"dead_reckoning_heading_error_rms_rad", r.dead_reckoning_heading_error_rms_rad},
      {"scans_registered", r.scans_registered},
      {"scans_not_registered", r.scans_not_registered},
      {"slips", r.slips},
      {"replans", r.replans},
      {"wall_s", r.wall_s},
      {"ground_busy_s", r.ground_work.total_s()},
      {"registering_s", r.ground_work.registering_s},
      {"mapping_s", r.ground_work.mapping_s},
      {"planning_s", r.ground_work.planning_s},
      {"modelled_execution_s", r.modelled_execution_s}};
  if (!r.stopped.empty()) out["stopped"] = r.stopped;
  if (log) {
    out["log"] = nlohmann::json::array();
    for (const auto& s : r.log) out["log"].push_back(stepJson(s));
  }
  return out;
}

struct Comparison {
  walk::WalkResult concurrent, sequential;
  double time_scale = 0.0;
  std::string time_scale_source = "given";
};

// The same walk planned concurrently and one step after the other. Without
// a given scale, execution is scaled to the Ambler's ratio to its ground
// work, measured on a sequential walk without waiting.
Comparison compareModes(const walk::WalkSetup& config, walk::WalkOptions o) {
  Comparison c;
  if (o.time_scale == 0.0) {
    o.concurrent = false;
    o.time_scale = walk::timeScaleOfTheReport(walk::runWalk(config, o));
    c.time_scale_source = "cmu-1990 fig. 6: execution takes 0.75 of the ground's work";
  }
  c.time_scale = o.time_scale;
  // Each is walked once first to warm the process up (the first walk in a
  // process pays for fresh memory), then timed.
  auto walkAs = [&](bool concurrent) {
    o.concurrent = concurrent;
    walk::runWalk(config, o);
    return walk::runWalk(config, o);
  };
  c.concurrent = walkAs(true);
  c.sequential = walkAs(false);
  return c;
}

// Wall time per step: the two modes may walk different steps, and a walk
// that stops early is not a faster one.
double wallSavingPct(const Comparison& c) {
  if (c.concurrent.steps == 0 || c.sequential.steps == 0) return 0.0;
  const double per_step = c.concurrent.wall_s / c.concurrent.steps;
  return 100.0 * (1.0 - per_step / (c.sequential.wall_s / c.sequential.steps));
}

walk::WalkSetup readConfig(const WalkArgs& a) {
  auto config_path = [](const std::string& given, const char* resource) {
    return given.empty() ? findResource(resource) : fs::path(given);
  };
  return walk::readWalkSetup(config_path(a.rover_config, "config/rover.json"),
                             config_path(a.footfall_config, "config/footfall.json"),
                             config_path(a.scanner_config, "config/rover-scanner.json"));
}

void runWalk(const WalkArgs& a) {
  const auto config = readConfig(a);
  walk::WalkOptions o = walk::onCourse(a.course, std::uint64_t(a.seed), a.steps);
  o.concurrent = !a.sequential;
  o.time_scale = a.time_scale;
  o.register_scans = !a.no_registration;
  o.heading = a.path.heading();
  if (!a.compare) {
    nlohmann::json out = resultJson(walk::runWalk(config, o), o.concurrent, a.log);
    out["seed"] = a.seed;
    out["time_scale"] = a.time_scale;
    printJson(out);
    return;
  }
  const auto c = compareModes(config, o);
  const auto& concurrent = c.concurrent;
  const auto& sequential = c.sequential;
  nlohmann::json out = resultJson(concurrent, true, a.log);
  out["sequential"] = resultJson(sequential, false, a.log);
  out["wall_saving_pct"] = wallSavingPct(c);
  out["seed"] = a.seed;
  out["time_scale"] = c.time_scale;
  out["time_scale_source"] = c.time_scale_source;
  printJson(out);
}

struct EvalWalkArgs {
  std::vector<std::uint64_t> seeds{1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  int steps = 100;
  std::string course = "traverse";
  int repetitions = 5;  // of the concurrent-against-sequential comparison
  bool json = true;     // the only output form
};

double percentOf(double error_m, double distance_m) {
  return distance_m > 0 ? 100.0 * error_m / distance_m : 0.0;
}

nlohmann::json walkJson(std::uint64_t seed, const walk::WalkResult& r) {
  nlohmann::json j = {
      {"seed", seed},
      {"steps", r.steps},
      {"distance_m", r.distance_m},
      {"csp_violations", r.csp_violations},
      {"leg_collisions", r.leg_collisions},
      {"min_stability_margin_m", r.min_stability_margin_m},
      {"registered",
       {{"final_m", r.pose_error_final_m},
        {"max_m", r.pose_error_max_m},
        {"rms_m", r.pose_error_rms_m},
        {"heading_rms_rad", r.heading_error_rms_rad},
        {"final_pct_of_distance", percentOf(r.pose_error_final_m, r.distance_m)}}},
      {"dead_reckoning",
       {{"final_m", r.dead_reckoning_error_final_m},
        {"max_m", r.dead_reckoning_error_max_m},
        {"rms_m", r.dead_reckoning_error_rms_m},
        {"heading_rms_rad", r.dead_reckoning_heading_error_rms_rad},
        {"final_pct_of_distance", percentOf(r.dead_reckoning_error_final_m, r.distance_m)}}},
      {"scans_registered", r.scans_registered},
      {"scans_not_registered", r.scans_not_registered}};
  if (!r.stopped.empty()) j["stopped"] = r.stopped;
  return j;
}

// Long walks (cmu-1990's loop, as ambler-gs runs it): stability, and the
// pose the ground places the rover at against the truth, with
// registration and by the rover's dead reckoning alone; then the wall
// time planning ahead saves, walk after walk.
nlohmann::json evalWalk(const EvalWalkArgs& a) {
  const auto config = readConfig(WalkArgs{});
  std::vector<double> distance, margin, pose_error, pose_pct, dr_error, dr_pct, pose_rms, dr_rms,
      plan_ms, saving;
  int violations = 0, collisions = 0, stopped = 0, not_worse = 0, rms_not_worse = 0;
  double total_m = 0.0, moving_s = 0.0;
  nlohmann::json walks = nlohmann::json::array();
  ProgressLine progress("eval walk", a.seeds.size() + std::size_t(std::max(a.repetitions, 0)));
  for (const auto seed : a.seeds) {
    progress.next(a.course + " seed " + std::to_string(seed) + ", " + std::to_string(a.steps) +
                  " steps");
    const auto r = walk::runWalk(config, walk::onCourse(a.course, seed, a.steps));
    walks.push_back(walkJson(seed, r));
    distance.push_back(r.distance_m);
    margin.push_back(r.min_stability_margin_m);
    pose_error.push_back(r.pose_error_final_m);
    pose_pct.push_back(percentOf(r.pose_error_final_m, r.distance_m));
    dr_error.push_back(r.dead_reckoning_error_final_m);
    dr_pct.push_back(percentOf(r.dead_reckoning_error_final_m, r.distance_m));
    pose_rms.push_back(r.pose_error_rms_m);
    dr_rms.push_back(r.dead_reckoning_error_rms_m);
    plan_ms.push_back(r.plan_ms_median);
    not_worse += r.pose_error_final_m <= r.dead_reckoning_error_final_m;
    rms_not_worse += r.pose_error_rms_m <= r.dead_reckoning_error_rms_m;
    violations += r.csp_violations, collisions += r.leg_collisions, stopped += !r.stopped.empty();
    total_m += r.distance_m, moving_s += r.modelled_execution_s;
  }
  for (int k = 0; k < a.repetitions && !a.seeds.empty(); ++k) {
    const auto seed = a.seeds[std::size_t(k) % a.seeds.size()];
    progress.next("planning ahead against one step at a time, " + a.course + " seed " +
                  std::to_string(seed));
    const auto c = compareModes(config, walk::onCourse(a.course, seed, a.steps));
    saving.push_back(wallSavingPct(c));
  }
  const auto spread = [](std::vector<double> v) -> nlohmann::json {
    if (v.empty()) return nullptr;
    std::sort(v.begin(), v.end());
    return {{"median", v[v.size() / 2]}, {"min", v.front()}, {"max", v.back()}, {"runs", v.size()}};
  };
  return {{"course", a.course},
          {"walks", a.seeds.size()},
          {"steps_per_walk", a.steps},
          {"walks_stopped_early", stopped},
          {"distance_m", distribution(distance)},
          {"min_csp_margin_m", distribution(margin)},
          {"csp_violations", violations},
          {"leg_collisions", collisions},
          {"pose_error_final_m", distribution(pose_error)},
          {"pose_error_final_pct", distribution(pose_pct)},
          {"dead_reckoning_error_final_m", distribution(dr_error)},
          {"dead_reckoning_error_final_pct", distribution(dr_pct)},
          {"walks_registration_not_worse", not_worse},
          {"pose_error_rms_m", distribution(pose_rms)},
          {"dead_reckoning_error_rms_m", distribution(dr_rms)},
          {"walks_registration_rms_not_worse", rms_not_worse},
          {"plan_ms_median", distribution(plan_ms)},
          {"wall_saving_pct", spread(saving)},
          {"speed_while_moving_m_per_min", moving_s > 0 ? 60.0 * total_m / moving_s : 0.0},
          {"per_walk", walks}};
}

}  // namespace

gait::Heading WalkPath::heading() const {
  if (!turn.empty()) return {0.0, turn == "left"};
  return radius_m != 0.0 ? gait::Heading{radius_m} : gait::Heading{};
}

void addWalkPathOptions(CLI::App& cmd, WalkPath& path) {
  auto* radius = cmd.add_option("--radius", path.radius_m,
                                "follow an arc of this radius [m], positive turns left "
                                "(default: straight)")
                     ->check(CLI::Validator(
                         [](const std::string& text) {
                           const double r = std::strtod(text.c_str(), nullptr);
                           return std::isfinite(r) && r != 0.0
                                      ? std::string()
                                      : "must be a finite number of metres other than 0 (a turn "
                                        "in place is --turn)";
                         },
                         "", "RADIUS"));
  cmd.add_option("--turn", path.turn, "turn in place instead: left or right")
      ->check(CLI::IsMember({"left", "right"}))
      ->excludes(radius);
}

void addWalk(CLI::App& app) {
  auto args = std::make_shared<WalkArgs>();
  auto* cmd = app.add_subcommand(
      "walk", "Walk the simulated Ambler autonomously across an obstacle course and print JSON");
  cmd->add_option("--seed", args->seed, "obstacle course and noise seed")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  cmd->add_option("--steps", args->steps, "steps (leg recovery + body move)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_option("--course", args->course,
                  "obstacle: the cmu-1990 high-bay course, 50 m (box, trench, ramp, boulders, "
                  "rocks); traverse: 90 m of its ground and rocks without box, trench and ramp; "
                  "rocks20: a Golombek-Rapp rock field of 20 % abundance; craters: a crater "
                  "field (docs/simulator.md), both 90 m as the traverse")
      ->check(CLI::IsMember({"obstacle", "traverse", "rocks20", "craters"}))
      ->capture_default_str();
  addWalkPathOptions(*cmd, args->path);
  cmd->add_flag("--sequential", args->sequential,
                "perceive, plan and execute one after the other (default: plan the next step "
                "while this one executes)");
  cmd->add_flag("--compare", args->compare,
                "also walk sequentially and print both, with the wall-time saving of planning "
                "concurrently")
      ->excludes("--sequential");
  cmd->add_flag("--no-registration", args->no_registration,
                "map and plan where the rover's dead reckoning says it is (default: register "
                "each scan against the map and correct the pose)");
  cmd->add_option("--time-scale", args->time_scale,
                  "wall seconds per simulated second of execution (default 0: no waiting; "
                  "with --compare, the Ambler's ratio of execution to ground work)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmd->add_flag("--log", args->log, "include every step in the JSON");
  cmd->add_flag("--json", args->json,
                "print JSON (the only output format; accepted for symmetry with eval)");
  cmd->add_option("--config", args->rover_config,
                  "rover, gait and simulation (default: resources/config/rover.json)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--footfall-config", args->footfall_config,
                  "foot, cost limits and weights (default: resources/config/footfall.json)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--scanner-config", args->scanner_config,
                  "walking scanner (default: resources/config/rover-scanner.json)")
      ->check(CLI::ExistingFile);
  cmd->callback([args] { runWalk(*args); });
}

void addEvalWalk(CLI::App& eval, Evaluations& all) {
  all.push_back({"walk", [] { return evalWalk(EvalWalkArgs{}); }});
  auto args = std::make_shared<EvalWalkArgs>();
  auto* cmd = eval.add_subcommand(
      "walk",
      "Long autonomous walks as ambler-gs walks: distance, stability, pose error against "
      "the truth with registration and by dead reckoning alone, and the wall time planning "
      "ahead saves");
  cmd->add_option("--seeds", args->seeds, "course seeds, one walk each (evaluation seeds 1-10)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--steps", args->steps, "steps per walk")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_option("--course", args->course,
                  "obstacle, traverse, rocks20 or craters (see walk --help)")
      ->check(CLI::IsMember({"obstacle", "traverse", "rocks20", "craters"}))
      ->capture_default_str();
  cmd->add_option("--repetitions", args->repetitions,
                  "concurrent-against-sequential comparisons, cycling through the seeds")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
  cmd->add_flag("--json", args->json, "print JSON (the only output form)");
  cmd->callback([args] { printJson(evalWalk(*args)); });
}

}  // namespace ambler::cli
