#pragma once

// A headless walk of the simulated Ambler, run as ambler-gs runs one: the
// walk executive over the in-process link, its approval gate in explicit
// auto-approve mode (every interlock still runs), the rover reporting its
// own dead-reckoned pose. Only the scoring sees the truth, through the
// link's observer, never the executive.

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "executive/WalkExecutive.h"
#include "gait/GaitPlanner.h"
#include "rover/SimulatedRover.h"

namespace ambler::walk {

struct WalkSetup {
  gait::GaitContext ground;           // what the ground station plans with
  rover::SimulatedRoverConfig rover;  // the simulated Ambler and how it errs
};

// rover.json, footfall.json and the walking scanner's JSON; errors name the
// file and key.
WalkSetup readWalkSetup(const std::filesystem::path& rover_json,
                        const std::filesystem::path& footfall_json,
                        const std::filesystem::path& scanner_json);
// The installed configuration (core/Resources.h).
WalkSetup readInstalledWalkSetup();

struct WalkOptions {
  sim::CourseOptions course;                       // its seed also draws the execution noise
  std::optional<sim::TerrainDescription> terrain;  // in place of the course
  int steps = 25;
  gait::Heading heading;  // straight ahead by default
  // Plan the next step while the current one executes (cmu-1990 TCA), or
  // scan, plan and execute one after the other.
  bool concurrent = true;
  // Wall seconds per simulated second of execution: the simulated rover
  // takes this long to answer a move or a scan (0: at once).
  double time_scale = 0.0;
  double map_resolution_m = 0.1;  // the report's cost maps are on a 10 cm grid
  bool register_scans = true;     // off: the ground trusts the rover's dead reckoning
  Box2 map_extent{-10.0, -8.0, 10.0, 45.0};
};

// The options of a walk on sim::longTraverse(seed): the map reaches to
// the traverse's far end.
WalkOptions onLongTraverse(std::uint64_t seed, int steps);
// The options of a walk on one of `ambler-cli walk`'s courses: "obstacle"
// (the cmu-1990 course), "traverse" (onLongTraverse), "rocks20" (a
// Golombek-Rapp rock field of 20 % abundance) or "craters" (a crater
// field), the last two on the traverse's field and map; std::invalid_argument
// for another name.
WalkOptions onCourse(std::string_view course, std::uint64_t seed, int steps);

struct WalkStep {
  int leg = -1;
  Eigen::Vector3d foothold{0, 0, 0};
  double body_u = 0.0;
  double plan_ms = 0.0;
  bool planned_ahead = false;
  // The body's pose after the step against the truth: where the ground
  // placed it (the rover's report, corrected by registering the scan taken
  // there) and where the rover's dead reckoning alone put it; heading errors
  // signed, estimate minus truth.
  double pose_error_m = 0.0;
  // The same error along the true heading and across it, to its left:
  // what drifts the walk, a bias along the track or a turn.
  double pose_error_along_m = 0.0, pose_error_across_m = 0.0;
  double dead_reckoning_error_m = 0.0;
  double dead_reckoning_error_along_m = 0.0, dead_reckoning_error_across_m = 0.0;
  double heading_error_rad = 0.0;
  double dead_reckoning_heading_error_rad = 0.0;
  std::string event;
  std::string reason;  // what stopped the body move (gait::StepPlan::reason)
};

// What `ambler-cli walk` prints (docs/gait.md).
struct WalkResult {
  int steps = 0;
  double distance_m = 0.0;  // true start to true end of the body
  double heading_change_deg = 0.0;
  double min_stability_margin_m = INFINITY;
  // The least margin had any one supporting foot failed at any moment (the
  // CSP's promise).
  double min_margin_one_foot_lost_m = INFINITY;
  int csp_violations = 0;  // trace samples with the true CoG outside the true CSP
  int leg_collisions = 0;
  double plan_ms_median = 0.0;
  // The ground's estimate of the body position against the truth, at the
  // end, the worst and the root mean square over the steps, and the
  // heading's root mean square; the same for the rover's dead reckoning
  // alone (equal when registration is off).
  double pose_error_final_m = 0.0;
  double pose_error_max_m = 0.0;
  double pose_error_rms_m = 0.0;
  double heading_error_rms_rad = 0.0;
  double dead_reckoning_error_final_m = 0.0;
  double dead_reckoning_error_max_m = 0.0;
  double dead_reckoning_error_rms_m = 0.0;
  double dead_reckoning_heading_error_rms_rad = 0.0;
  int scans_registered = 0;
  int scans_not_registered = 0;  // refused, the first scan included
  int slips = 0;                 // feet the simulator slipped
  int replans =
      0;  // steps planned afresh: the rover ended off its prediction, or a leg stopped early
  double wall_s = 0.0;
  executive::GroundWork ground_work;  // registration, mapping and planning, wall time
  double modelled_execution_s = 0.0;  // the rover's moves and scans, simulated time
  std::string stopped;                // why the walk ended early, empty when it did not
  std::vector<WalkStep> log;
};

// cmu-1990: scan -> register against the map -> map (locus) -> merge ->
// footfall cost maps -> gait plan -> leg recovery -> execute, on
// `options.course`, `options.steps` times.
WalkResult runWalk(const WalkSetup& setup, const WalkOptions& options);

// The time_scale that makes a walk's execution take 0.75 of its ground work,
// the Ambler's ratio (cmu-1990 fig. 6), from a walk run with time_scale 0:
// this computer plans far faster than the Ambler's did, so its execution is
// scaled down by as much. 0 when the probe walked no step.
double timeScaleOfTheReport(const WalkResult& probe);

}  // namespace ambler::walk
