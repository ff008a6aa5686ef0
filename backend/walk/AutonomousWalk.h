#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "gait/GaitPlanner.h"
#include "sim/RoverSim.h"
#include "sim/ScannerSim.h"

namespace ambler::walk {

// Everything a simulated walk reads from the configuration files.
struct WalkConfig {
  gait::GaitContext gait;
  sim::ExecutionNoise noise;
  sim::ScannerModel scanner;
};

// rover.json (rover, gait, recovery, simulation), footfall.json and the
// walking scanner's JSON; errors name the file and key.
WalkConfig readWalkConfig(const std::filesystem::path& rover_json,
                          const std::filesystem::path& footfall_json,
                          const std::filesystem::path& scanner_json);
// The installed configuration: config/rover.json, config/footfall.json and
// config/rover-scanner.json from the resources (core/Resources.h).
WalkConfig readDefaultWalkConfig();

struct WalkOptions {
  std::uint64_t seed = 1;  // obstacle course and execution noise
  int steps = 25;
  gait::Heading heading;  // straight ahead by default
  // Plan the next step while the current one executes (cmu-1990 TCA), or
  // perceive, plan and execute one after the other.
  bool concurrent = true;
  // Wall seconds per simulated second of execution: the simulator waits
  // this long so execution takes real time (0: no waiting).
  double time_scale = 0.0;
  double map_resolution_m = 0.1;  // the report's cost maps are on a 10 cm grid
  Box2 map_extent{-10.0, -8.0, 10.0, 45.0};
};

struct WalkStep {
  int leg = -1;
  Eigen::Vector3d foothold{0, 0, 0};
  double body_u = 0.0;
  double plan_ms = 0.0;
  double execute_s = 0.0;  // simulated
  double csp_margin_m = 0.0;
  double dead_reckoning_error_m = 0.0;
  int slipped_feet_detected = 0;
  bool replanned = false;
  std::string event;
};

// What `ambler-cli walk` prints (docs/gait.md).
struct WalkResult {
  int steps = 0;
  double distance_m = 0.0;  // true start to true end of the body
  double heading_change_deg = 0.0;
  double min_stability_margin_m = INFINITY;
  int csp_violations = 0;  // trace samples with the true CoG outside the true CSP
  int leg_collisions = 0;
  double plan_ms_median = 0.0;
  double dead_reckoning_error_m = 0.0;  // worst over body moves
  double dead_reckoning_drift_m = 0.0;  // estimated vs true position at the end
  int slips = 0;                        // feet the simulator slipped
  int slips_detected = 0;
  int replans = 0;    // steps planned again after execution (concurrent mode)
  int rechecked = 0;  // steps kept after rechecking them on the real stance
  double wall_s = 0.0;
  double ground_busy_s = 0.0;         // mapping and planning, wall time
  double modelled_execution_s = 0.0;  // the rover's moves and scans, simulated time
  std::string stopped;                // why the walk ended early, empty when it did not
  std::vector<WalkStep> log;
  std::vector<sim::SupportSample> trace;
};

// cmu-1990: scan -> map (locus) -> merge -> footfall cost maps -> gait plan
// -> leg recovery -> execute -> kinematic dead reckoning, on the obstacle
// course of `options.seed`, `options.steps` times.
WalkResult runWalk(const WalkConfig& config, const WalkOptions& options);

// The time_scale that makes a walk's execution take 0.75 of its ground work,
// the Ambler's ratio (cmu-1990 fig. 6), from a walk run with time_scale 0:
// this computer plans far faster than the Ambler's did, so its execution is
// scaled down by as much. 0 when the probe walked no step.
double timeScaleOfTheReport(const WalkResult& probe);

}  // namespace ambler::walk
