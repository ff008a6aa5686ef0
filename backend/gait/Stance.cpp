#include "gait/Stance.h"

#include <cmath>
#include <cstdio>

namespace ambler::gait {

Eigen::Matrix2d BodyPose::rotation() const {
  const double c = std::cos(heading_rad), s = std::sin(heading_rad);
  return (Eigen::Matrix2d() << c, -s, s, c).finished();
}

Eigen::Vector3d BodyPose::toWorld(const Eigen::Vector3d& body) const {
  const Eigen::Vector2d p = toWorld(Eigen::Vector2d(body.head<2>()));
  return {p.x(), p.y(), body.z() + link_z};
}

Eigen::Vector3d BodyPose::toBody(const Eigen::Vector3d& world) const {
  const Eigen::Vector2d p = toBody(Eigen::Vector2d(world.head<2>()));
  return {p.x(), p.y(), world.z() - link_z};
}

double Heading::turnPerUnit() const {
  if (isPointTurn()) return point_turn_left ? 1.0 : -1.0;
  return std::isinf(radius_m) ? 0.0 : 1.0 / radius_m;
}

BodyPose Heading::advance(const BodyPose& start, double u) const {
  const double v = forwardPerUnit(), w = turnPerUnit();
  const double turn = w * u;
  // Exact integration of a constant twist; forward is body +y.
  Eigen::Vector2d d;
  if (std::abs(turn) < 1e-9)
    d = {0.0, v * u};
  else
    d = {-(v / w) * (1.0 - std::cos(turn)), (v / w) * std::sin(turn)};
  BodyPose p = start;
  p.xy = start.toWorld(d);
  p.heading_rad = start.heading_rad + turn;
  return p;
}

Eigen::Vector2d Heading::motionAt(const Eigen::Vector2d& body_point) const {
  const double w = turnPerUnit();
  const Eigen::Vector2d v =
      Eigen::Vector2d(0.0, forwardPerUnit()) + w * Eigen::Vector2d(-body_point.y(), body_point.x());
  const double n = v.norm();
  return n > 1e-12 ? Eigen::Vector2d(v / n) : Eigen::Vector2d(0.0, 1.0);
}

std::string describe(const Heading& h) {
  if (h.isPointTurn())
    return h.point_turn_left ? "turning left in place" : "turning right in place";
  if (!std::isfinite(h.radius_m)) return "straight";
  char radius[32];
  std::snprintf(radius, sizeof radius, "%.1f", std::abs(h.radius_m));
  return std::string("on an arc of ") + radius + " m radius to the " +
         (h.radius_m > 0 ? "left" : "right");
}

std::string constraintName(Constraint c) {
  switch (c) {
    case Constraint::kNone:
      return "none";
    case Constraint::kLegLeg:
      return "leg-leg";
    case Constraint::kLegBody:
      return "leg-body";
    case Constraint::kKinematic:
      return "kinematic limits";
    case Constraint::kConservativeSupport:
      return "conservative support polygon";
  }
  return "?";
}

std::vector<Eigen::Vector2d> Stance::supportingFeet(int except) const {
  std::vector<Eigen::Vector2d> out;
  for (int i = 0; i < kLegCount; ++i)
    if (supporting[std::size_t(i)] && i != except) out.push_back(feet[std::size_t(i)].head<2>());
  return out;
}

namespace {

// `settled(i, j)`: feet i and j need not keep the leg separation;
// `tolerated(i, q)`: foot i may stand beyond its leg's limits at joints q.
template <typename Settled, typename Tolerated>
StanceCheck check(const Stance& stance, const RoverModel& model, double csp_margin, Settled settled,
                  Tolerated tolerated) {
  StanceCheck check;
  const Eigen::Matrix2d to_body = stance.body.rotation().transpose();  // once: sin/cos are dear
  for (int i = 0; i < kLegCount; ++i) {
    if (!stance.supporting[std::size_t(i)]) continue;
    const Eigen::Vector3d& w = stance.feet[std::size_t(i)];
    const Eigen::Vector2d f = to_body * (w.head<2>() - stance.body.xy);
    const LegJoints q{0.0, (f - model.shaftOf(i)).norm(), stance.body.link_z - w.z()};
    if (!model.withinLimits(q) && !tolerated(i, q)) return {Constraint::kKinematic, i};
    const Eigen::Vector2d k = model.body_keepout_half;
    if (std::abs(f.x()) < k.x() && std::abs(f.y()) < k.y()) return {Constraint::kLegBody, i};
    for (const auto& shaft : model.shafts)
      if ((f - shaft).norm() < model.shaft_clearance_m) return {Constraint::kLegBody, i};
    for (int j = i + 1; j < kLegCount; ++j)
      if (stance.supporting[std::size_t(j)] && !settled(i, j) &&
          (stance.feet[std::size_t(i)] - stance.feet[std::size_t(j)]).head<2>().norm() <
              model.min_leg_separation_m)
        return {Constraint::kLegLeg, i};
  }
  check.csp_margin_m = conservativeMargin(stance.supportingFeet(), stance.centreOfGravity(model));
  if (check.csp_margin_m < csp_margin) check.violated = Constraint::kConservativeSupport;
  return check;
}

}  // namespace

StanceCheck checkStance(const Stance& stance, const RoverModel& model, double csp_margin) {
  return check(
      stance, model, csp_margin, [](int, int) { return false; },
      [](int, const LegJoints&) { return false; });
}

StanceCheck checkStance(const Stance& stance, const Stance& from, const RoverModel& model,
                        double csp_margin) {
  const auto stood = [&](int i) {
    return from.supporting[std::size_t(i)] &&
           stance.feet[std::size_t(i)] == from.feet[std::size_t(i)];
  };
  const auto closer = [&](int i, const LegJoints& q) {
    return stood(i) && model.beyondLimits(q) < model.beyondLimits(from.joints(model, i));
  };
  return check(
      stance, model, csp_margin, [&](int i, int j) { return stood(i) && stood(j); }, closer);
}

double marginWithout(const Stance& stance, const RoverModel& model, int leg) {
  return conservativeMargin(stance.supportingFeet(leg), stance.centreOfGravity(model));
}

std::vector<int> liftableLegs(const Stance& stance, const RoverModel& model, double csp_margin) {
  std::vector<int> legs;
  for (int i = 0; i < kLegCount; ++i)
    if (stance.supporting[std::size_t(i)] && marginWithout(stance, model, i) >= csp_margin)
      legs.push_back(i);
  return legs;
}

Stance moveBody(const Stance& stance, const Heading& heading, double u) {
  Stance moved = stance;
  moved.body = heading.advance(stance.body, u);
  return moved;
}

BodyMoveLimit maxBodyMove(const Stance& stance, const Heading& heading, const RoverModel& model,
                          double csp_margin, double u_max, double step) {
  BodyMoveLimit limit;
  for (double u = step;; u += step) {
    const double at = std::min(u, u_max);
    const StanceCheck c = checkStance(moveBody(stance, heading, at), stance, model, csp_margin);
    if (!c.ok()) return {limit.u, c.violated, c.leg};
    limit.u = at;
    if (at >= u_max) return limit;
  }
}

}  // namespace ambler::gait
