// ambler-cli walk: a headless autonomous walk across the simulated obstacle
// course (cmu-1990: scan, map, merge, footfall, gait plan, execute).
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
                      {"execute_s", s.execute_s},
                      {"csp_margin_m", s.csp_margin_m},
                      {"dead_reckoning_error_m", s.dead_reckoning_error_m},
                      {"slipped_feet_detected", s.slipped_feet_detected},
                      {"replanned", s.replanned},
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
                        {"dead_reckoning_error_m", r.dead_reckoning_error_m},
                        {"dead_reckoning_drift_m", r.dead_reckoning_drift_m},
                        {"slips", r.slips},
                        {"slips_detected", r.slips_detected},
                        {"replans", r.replans},
                        {"rechecked", r.rechecked},
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

void runWalk(const WalkArgs& a) {
  auto config_path = [](const std::string& given, const char* resource) {
    return given.empty() ? findResource(resource) : fs::path(given);
  };
  const auto config =
      walk::readWalkConfig(config_path(a.rover_config, "config/rover.json"),
                           config_path(a.footfall_config, "config/footfall.json"),
                           config_path(a.scanner_config, "config/rover-scanner.json"));
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
  // Without a given scale, execution is scaled to the Ambler's ratio to its
  // ground work, measured on a sequential walk without waiting.
  std::string scale_source = "given";
  if (a.time_scale == 0.0) {
    o.concurrent = false;
    o.time_scale = walk::timeScaleOfTheReport(walk::runWalk(config, o));
    scale_source = "cmu-1990 fig. 6: execution takes 0.75 of the ground's work";
  }
  // The same walk planned concurrently and one step after the other. Each
  // is walked once first to warm the process up (the first walk in a
  // process pays for fresh memory), then timed.
  auto walkAs = [&](bool concurrent) {
    o.concurrent = concurrent;
    walk::runWalk(config, o);
    return walk::runWalk(config, o);
  };
  const auto concurrent = walkAs(true);
  const auto sequential = walkAs(false);
  nlohmann::json out = resultJson(concurrent, true, a.log);
  out["sequential"] = resultJson(sequential, false, a.log);
  out["wall_saving_pct"] = 100.0 * (1.0 - concurrent.wall_s / sequential.wall_s);
  out["seed"] = a.seed;
  out["time_scale"] = o.time_scale;
  out["time_scale_source"] = scale_source;
  printJson(out);
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

}  // namespace ambler::cli
