#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "gait/RoverModel.h"
#include "gait/Support.h"

namespace ambler::gait {

// The level body's pose: position of its vertical axis on the ground plane,
// heading counter-clockwise about +z (0: body +y along world +y), and the
// height of the link plane in the world.
struct BodyPose {
  Eigen::Vector2d xy{0.0, 0.0};
  double heading_rad = 0.0;
  double link_z = 2.4;

  Eigen::Matrix2d rotation() const;
  Eigen::Vector2d toWorld(const Eigen::Vector2d& body) const { return xy + rotation() * body; }
  Eigen::Vector2d toBody(const Eigen::Vector2d& world) const {
    return rotation().transpose() * (world - xy);
  }
  Eigen::Vector3d toWorld(const Eigen::Vector3d& body) const;
  Eigen::Vector3d toBody(const Eigen::Vector3d& world) const;
};

// The direction the walk follows: an arc of radius `radius_m` (positive
// turns left), a straight line (infinite radius) or a point turn (radius
// 0, `point_turn_left` gives the sense). A body move is a parameter u
// along it: metres of travel, or radians of rotation for a point turn.
struct Heading {
  double radius_m = INFINITY;
  bool point_turn_left = true;

  bool isPointTurn() const { return radius_m == 0.0; }
  // Forward speed and turn rate per unit of u in the body frame.
  double forwardPerUnit() const { return isPointTurn() ? 0.0 : 1.0; }
  double turnPerUnit() const;
  // The pose after moving u along the arc from `start` (link_z kept).
  BodyPose advance(const BodyPose& start, double u) const;
  // Direction a body point moves in, body frame, unit length.
  Eigen::Vector2d motionAt(const Eigen::Vector2d& body_point) const;
};

// "straight", "on an arc of 10.0 m radius to the left", "turning
// left in place".
std::string describe(const Heading& heading);

// Where the feet are: world positions of the soles, and which legs stand.
struct Stance {
  BodyPose body;
  // Zero, not left unset as Eigen's own default leaves them.
  std::array<Eigen::Vector3d, kLegCount> feet = [] {
    std::array<Eigen::Vector3d, kLegCount> zero;
    zero.fill(Eigen::Vector3d::Zero());
    return zero;
  }();
  std::array<bool, kLegCount> supporting{true, true, true, true, true, true};

  std::vector<Eigen::Vector2d> supportingFeet(int except = -1) const;
  Eigen::Vector2d centreOfGravity(const RoverModel& model) const {
    return body.toWorld(model.centre_of_gravity);
  }
  LegJoints joints(const RoverModel& model, int leg) const {
    return model.jointsFor(leg, body.toBody(feet[std::size_t(leg)]));
  }
};

// The four ways legs stop the body (cmu-1990 'Planning strategies', Gaits),
// plus the vertical range of the legs.
enum class Constraint { kNone, kLegLeg, kLegBody, kKinematic, kConservativeSupport };
std::string constraintName(Constraint c);

struct StanceCheck {
  Constraint violated = Constraint::kNone;
  int leg = -1;               // the leg at fault, when one is
  double csp_margin_m = 0.0;  // of the centre of gravity
  bool ok() const { return violated == Constraint::kNone; }
};

// Checks every supporting leg against the rover's limits and the centre
// of gravity against the conservative support polygon with `csp_margin`.
StanceCheck checkStance(const Stance& stance, const RoverModel& model, double csp_margin);

// As above, for a stance reached from `from`, except that two feet both
// standing where they stood in `from` need not keep the leg separation:
// neither moves, so their separation cannot change, and only lifting one of
// them restores it (after a foot slipped into it). Likewise a foot standing
// where it stood beyond its leg's limits (a slip) may stay beyond them when
// the body has moved it closer to them: moving toward it is the way back,
// and the same rule holds for the planner and the interlocks.
StanceCheck checkStance(const Stance& stance, const Stance& from, const RoverModel& model,
                        double csp_margin);

// CSP margin of the stance with `leg` lifted (the other legs as they are).
double marginWithout(const Stance& stance, const RoverModel& model, int leg);

// The legs that may be lifted now: the rest keep the centre of gravity in
// their conservative support polygon with `csp_margin`.
std::vector<int> liftableLegs(const Stance& stance, const RoverModel& model, double csp_margin);

// The largest body move along `heading`, at most `u_max`, that keeps every
// intermediate stance valid (sampled every `step` of u), and the constraint
// that stopped it (kNone when u_max was reached).
struct BodyMoveLimit {
  double u = 0.0;
  Constraint stopped_by = Constraint::kNone;
  int leg = -1;
};
BodyMoveLimit maxBodyMove(const Stance& stance, const Heading& heading, const RoverModel& model,
                          double csp_margin, double u_max, double step);

Stance moveBody(const Stance& stance, const Heading& heading, double u);

}  // namespace ambler::gait
