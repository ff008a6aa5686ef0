#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "gait/Stance.h"

namespace ambler::gait {

// cmu-1990 'Single leg walking' §6: the recovering leg's path is searched
// in the 2-D space of its horizontal joints (rotation, extension) on a grid
// of about 0.1 rad, with the foot's height chosen along the way, so a move
// through 3-D space costs a 2-D search. Terrain and the other legs are
// grown by the foot radius plus an uncertainty; A* minimises time plus
// `power_time_ratio` times energy (expressed in seconds of recovery power).
struct RecoveryOptions {
  double rotation_step_rad = 0.1;
  double extension_step_m = 0.1;
  double clearance_m = 0.15;      // sole above the grown terrain
  double uncertainty_m = 0.10;    // added to the foot radius when growing obstacles
  double power_time_ratio = 1.0;  // weight of energy against time
  double leg_mass_kg = 250.0;     // lifted with the foot (assumed)
  double gravity_m_s2 = 9.81;
};

// Height the sole must clear above world (x, y) for a foot disk of
// `radius` centred there [m]; NaN where the terrain is not known (the leg
// then lifts as high as it can).
using ClearanceField = std::function<double(const Eigen::Vector2d& world_xy, double radius)>;

struct RecoveryPlan {
  bool found = false;
  std::vector<LegJoints> waypoints;  // lift, path, above the goal, touch-down
  double time_s = 0.0;               // at full joint speed
  double energy_j = 0.0;
  double max_lift_m = 0.0;  // highest sole above its start [m]
  int expanded = 0;         // A* nodes
};

// Plans `leg` from its foot in `stance` to `goal` (world sole position).
// The other legs stand where `stance` has them. The last waypoint aims
// `touchdown_overshoot` below the goal, or as far as the leg's vertical
// travel allows, so the controller's contact stop ends the move (cmu-1990
// 'Real-time control'). Every waypoint is within the leg's limits.
RecoveryPlan planLegRecovery(const RoverModel& model, const Stance& stance, int leg,
                             const Eigen::Vector3d& goal, const ClearanceField& clearance,
                             const RecoveryOptions& options = {}, double touchdown_overshoot = 0.1);

// The lift-off waypoint: straight up from the joints the leg stands at to
// `vertical_m`, since the controller does not move a leg horizontally before
// lift-off (cmu-1990 'Real-time control'). A reported extension can read
// past its limit by the encoder's noise where the leg really stands at it;
// the lift is commanded at the limit.
LegJoints liftOff(const LegJoints& standing, double vertical_m, const RoverModel& model);

// Where the sole of `leg` passes in the world as it follows `plan` from
// `stance` (joints interpolated as the controller moves them, all arriving
// together), ending where the contact stops it at `goal`'s height.
std::vector<Eigen::Vector3d> footPath(const RoverModel& model, const Stance& stance, int leg,
                                      const RecoveryPlan& plan, const Eigen::Vector3d& goal,
                                      int samples_per_segment = 8);

}  // namespace ambler::gait
