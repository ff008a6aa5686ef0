// ambler-cli walk: a headless autonomous walk across the simulated obstacle
// course (cmu-1990: scan, map, merge, footfall, gait plan, execute), by the
// walk executive ambler-gs runs, auto-approving steps that pass every
// interlock.
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
  double radius = 0.0;  // 0: straight
  std::string turn;     // left | right: point turn
  bool sequential = false;
  bool compare = false;
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
                      {"event", s.event}};
  if (s.leg >= 0) j["foothold"] = {s.foothold.x(), s.foothold.y(), s.foothold.z()};
  return j;
}

nlohmann::json resultJson(const walk::WalkResult& r, bool concurrent, bool log) {
  nlohmann::json out = {{"mode", concurrent ? "concurrent" : "sequential"},
                        {"steps", r.steps},
                        {"distance_m", r.distance_m},
                        {"heading_change_deg", r.heading_change_deg},
                        {"min_stability_margin_m", r.min_stability_margin_m},
                        {"csp_violations", r.csp_violations},
                        {"leg_collisions", r.leg_collisions},
                        {"plan_ms_median", r.plan_ms_median},
                        {"pose_error_final_m", r.pose_error_final_m},
                        {"pose_error_max_m", r.pose_error_max_m},
                        {"slips", r.slips},
                        {"replans", r.replans},
                        {"wall_s", r.wall_s},
                        {"ground_busy_s", r.ground_busy_s},
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
  walk::WalkOptions o;
  o.seed = std::uint64_t(a.seed);
  o.steps = a.steps;
  o.concurrent = !a.sequential;
  o.time_scale = a.time_scale;
  if (!a.turn.empty())
    o.heading = {0.0, a.turn == "left"};
  else if (a.radius != 0.0)
    o.heading.radius_m = a.radius;
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
  out["wall_saving_pct"] = 100.0 * (1.0 - concurrent.wall_s / sequential.wall_s);
  out["seed"] = a.seed;
  out["time_scale"] = c.time_scale;
  out["time_scale_source"] = c.time_scale_source;
  printJson(out);
}

struct EvalWalkArgs {
  std::vector<std::uint64_t> seeds{1, 2, 3, 4, 5};
  int steps = 25;
  bool json = true;  // the only output form
};

// Straight walks across the course, each planned concurrently and
// sequentially (cmu-1990: concurrency saved over 30 % of the walking time).
nlohmann::json evalWalk(const EvalWalkArgs& a) {
  const auto config = readConfig(WalkArgs{});
  std::vector<double> distance, margin, pose_error, plan_ms, saving;
  int violations = 0, collisions = 0, stopped = 0;
  double concurrent_s = 0.0, sequential_s = 0.0, total_m = 0.0, moving_s = 0.0;
  for (const auto seed : a.seeds) {
    walk::WalkOptions o;
    o.seed = seed;
    o.steps = a.steps;
    const auto c = compareModes(config, o);
    const auto& r = c.concurrent;
    distance.push_back(r.distance_m);
    margin.push_back(r.min_stability_margin_m);
    pose_error.push_back(r.pose_error_final_m);
    plan_ms.push_back(r.plan_ms_median);
    saving.push_back(100.0 * (1.0 - r.wall_s / c.sequential.wall_s));
    violations += r.csp_violations, collisions += r.leg_collisions, stopped += !r.stopped.empty();
    concurrent_s += r.wall_s, sequential_s += c.sequential.wall_s;
    total_m += r.distance_m, moving_s += r.modelled_execution_s;
  }
  return {{"walks", a.seeds.size()},
          {"steps_per_walk", a.steps},
          {"walks_stopped_early", stopped},
          {"distance_m", distribution(distance)},
          {"min_csp_margin_m", distribution(margin)},
          {"csp_violations", violations},
          {"leg_collisions", collisions},
          {"pose_error_final_m", distribution(pose_error)},
          {"plan_ms_median", distribution(plan_ms)},
          {"wall_saving_pct", distribution(saving)},
          {"wall_saving_pct_total", 100.0 * (1.0 - concurrent_s / sequential_s)},
          {"speed_while_moving_m_per_min", moving_s > 0 ? 60.0 * total_m / moving_s : 0.0}};
}

}  // namespace

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
  auto* radius = cmd->add_option("--radius", args->radius,
                                 "follow an arc of this radius [m], positive turns left "
                                 "(default: straight)");
  cmd->add_option("--turn", args->turn, "turn in place instead: left or right")
      ->check(CLI::IsMember({"left", "right"}))
      ->excludes(radius);
  cmd->add_flag("--sequential", args->sequential,
                "perceive, plan and execute one after the other (default: plan the next step "
                "while this one executes)");
  cmd->add_flag("--compare", args->compare,
                "also walk sequentially and print both, with the wall-time saving of planning "
                "concurrently")
      ->excludes("--sequential");
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
      "Autonomous walks across simulated courses, planned concurrently and sequentially: "
      "distance, stability, dead reckoning and the wall time concurrency saves");
  cmd->add_option("--seeds", args->seeds, "course seeds, one walk each")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--steps", args->steps, "steps per walk")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_flag("--json", args->json, "print JSON (the only output form)");
  cmd->callback([args] { printJson(evalWalk(*args)); });
}

}  // namespace ambler::cli
