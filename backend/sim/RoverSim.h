#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "gait/Stance.h"
#include "sim/Terrain.h"

namespace ambler::sim {

// Execution errors of the simulated Ambler (resources/config/rover.json,
// section "simulation"). The encoder noise is on what the rover reports;
// the placement and body errors are on where it really goes.
struct ExecutionNoise {
  double encoder_rotation_rad = 0.0005;
  double encoder_extension_m = 0.002;
  double encoder_vertical_m = 0.002;
  double placement_m = 0.005;      // leg tracking error at touch-down
  double body_m = 0.01;            // body move error, per metre moved
  double body_rad = 0.002;         // heading error, per body move
  double slip_probability = 0.03;  // per supporting foot and body move
  double slip_m = 0.05;            // a slipped foot slides this far
  // The ground giving under the whole stance (loose soil): body and feet
  // slide together, which the legs cannot sense, so dead reckoning drifts
  // by it. Standard deviations per metre of body travel.
  double ground_creep_m = 0.02;     // along each horizontal axis
  double ground_creep_rad = 0.002;  // about the vertical, around the body
  std::uint64_t seed = 1;
};

ExecutionNoise readExecutionNoise(const std::filesystem::path& rover_json);

// cmu-1990 'Real-time control': a leg move is a list of joint waypoints;
// between waypoints the joints move so that all arrive together.
struct LegMove {
  int leg = 0;
  std::vector<gait::LegJoints> waypoints;
};

// A body move: translation in the current body frame and a rotation about
// the vertical, executed with a trapezoidal velocity profile; the link
// plane rises (or sinks) by `raise_m` on the way.
struct BodyMove {
  Eigen::Vector2d translation{0.0, 0.0};
  double rotation_rad = 0.0;
  double raise_m = 0.0;
};

// What the rover reports of one leg.
struct LegState {
  gait::LegJoints joints;  // encoder readings
  bool contact = false;    // force sensor over its threshold
  double force_n = 0.0;    // what the force sensor reads [N]
};

// The encoder readings of every leg.
std::array<gait::LegJoints, gait::kLegCount> jointsOf(
    const std::array<LegState, gait::kLegCount>& legs);

struct MoveReport {
  bool completed = true;  // false when a contact stopped the move early
  std::string event;      // "", "touch-down", "unexpected contact", "kinematic limit"
  double duration_s = 0.0;
  int collisions = 0;
  double min_csp_margin_m = INFINITY;  // true CoG in the true CSP, over the move
};

// One moment of the walk as it really was: the supporting feet and the
// centre of gravity (for the single-leg-failure test).
struct SupportSample {
  std::vector<Eigen::Vector2d> feet;
  Eigen::Vector2d centre_of_gravity;
};

class RoverSim {
 public:
  RoverSim(const Terrain& terrain, gait::RoverModel model, ExecutionNoise noise,
           gait::Stance start);

  MoveReport executeLeg(const LegMove& move);
  MoveReport executeBody(const BodyMove& move);

  std::array<LegState, gait::kLegCount> legStates();
  const gait::Stance& truth() const { return truth_; }
  const std::vector<SupportSample>& trace() const { return trace_; }
  int slips() const { return slips_; }

 private:
  double soleClearanceNeeded(const Eigen::Vector2d& xy) const;
  [[nodiscard]] bool slideSole(Eigen::Vector3d& sole, const Eigen::Vector2d& to) const;
  void record(double* min_margin, int lifted = -1);
  Eigen::Vector3d footAt(int leg, const gait::LegJoints& joints) const;
  // Within a foot's diameter of a supporting foot, across the ground.
  bool nearASupportingFoot(const Eigen::Vector3d& foot) const;
  bool followSegment(int leg, gait::LegJoints& q, gait::LegJoints target, bool touch_down,
                     MoveReport& report) const;
  void creep(double distance_m);

  const Terrain& terrain_;
  gait::RoverModel model_;
  ExecutionNoise noise_;
  gait::Stance truth_;
  std::mt19937_64 rng_;
  std::vector<SupportSample> trace_;
  int slips_ = 0;
};

// The vertical loads on the feet of a rover standing still: the
// minimum-norm forces that carry its weight with no moment about the
// centre of gravity [N], zero on lifted feet. With more than three feet
// the real split depends on the legs' compliance; this is the simulator's
// stand-in for it. Negative loads (centre of gravity outside the support)
// are clipped to zero.
std::array<double, gait::kLegCount> footLoads(const gait::Stance& stance,
                                              const gait::RoverModel& model);

// Drops the feet of `stance` onto the terrain (sole z = ground under the
// disk) and sets the link plane to the nominal height above them. Throws
// NoGroundError naming the first foot with no ground under it.
gait::Stance settleOnTerrain(gait::Stance stance, const Terrain& terrain,
                             const gait::RoverModel& model);

}  // namespace ambler::sim
