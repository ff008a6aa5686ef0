#include "executive/Interlocks.h"

#include <algorithm>
#include <sstream>

#include "link/Limits.h"
#include "terrain/Queries.h"

namespace ambler::executive {

namespace {

InterlockCheck planned(const gait::StepPlan& plan) {
  return {"plan", plan.ok, plan.ok ? plan.reason : "no step: " + plan.reason};
}

InterlockCheck jointLimits(const std::vector<link::CommandBody>& commands,
                           const gait::GaitContext& ctx) {
  for (const auto& command : commands) {
    if (const auto outside = link::outsideLimits(command, ctx.model, ctx.gait); outside.refused())
      return {"joint limits", false, outside.why()};
  }
  return {"joint limits", true, "every waypoint and the body move within the rover's limits"};
}

// The foot can be put down where planned: the joints for the foothold, from
// the body as it stands during the leg move, are inside their ranges.
InterlockCheck reach(const gait::StepPlan& plan, const gait::GaitContext& ctx) {
  if (plan.leg < 0) return {"reach", true, "no leg moves"};
  const auto& m = ctx.model;
  const gait::LegJoints q = m.jointsFor(plan.leg, plan.after_leg.body.toBody(plan.foothold));
  const std::string where = "leg " + std::to_string(plan.leg) + " extension " +
                            metres(q.extension_m) + ", vertical " + metres(q.vertical_m);
  if (!m.withinLimits(q))
    return {"reach", false,
            where + ": outside " + metres(m.extension_min_m) + "-" + metres(m.extension_max_m) +
                " and " + metres(m.vertical_min_m) + "-" + metres(m.vertical_max_m)};
  return {"reach", true, where};
}

// cmu-1990: the centre of gravity stays in the conservative support polygon
// with the margin while the leg is lifted, after it is placed, and after
// the body move.
InterlockCheck stability(const gait::StepPlan& plan, const gait::Stance& from,
                         const gait::GaitContext& ctx) {
  const auto& m = ctx.model;
  const double margin = ctx.gait.csp_margin_m;
  double lowest = INFINITY;
  std::string when;
  auto consider = [&](double value, const std::string& phase) {
    if (value < lowest) lowest = value, when = phase;
  };
  const auto placed = gait::checkStance(plan.after_leg, from, m, margin);
  const auto moved = gait::checkStance(plan.after, from, m, margin);
  if (plan.leg >= 0) {
    consider(gait::marginWithout(from, m, plan.leg), "while the leg is lifted");
    consider(placed.csp_margin_m, "after the foot is placed");
  }
  consider(moved.csp_margin_m, "after the body move");
  std::string detail =
      "least CSP margin " + metres(lowest) + " " + when + " (limit " + metres(margin) + ")";
  // A body move alone changes nothing before it: a stance the rover reports
  // below the margin (after a slip) is where it stands either way, and
  // moving the body is what takes it back in.
  if (plan.leg < 0) detail += "; " + metres(gait::marginWithout(from, m, -1)) + " before it";
  // Without a leg move nothing is placed: the body move is what takes a
  // stance the rover reports just beyond a limit (a slipped foot) back in.
  if (plan.leg >= 0 && !placed.ok() && placed.violated != gait::Constraint::kConservativeSupport)
    return {"stability", false,
            gait::constraintName(placed.violated) + " after the foot is placed; " + detail};
  if (!moved.ok() && moved.violated != gait::Constraint::kConservativeSupport)
    return {"stability", false,
            gait::constraintName(moved.violated) + " after the body move; " + detail};
  return {"stability", lowest >= margin, detail};
}

// Every cell under the foot is known: a foot set down in shadow, on ground
// never seen or on ground seen only at a grazing angle may meet anything.
InterlockCheck footholdTerrain(const gait::StepPlan& plan, const terrain::ElevationMap& map,
                               const gait::GaitContext& ctx) {
  if (plan.leg < 0) return {"foothold terrain", true, "no foot is set down"};
  const Disk foot{plan.foothold.head<2>(), 0.5 * ctx.model.foot_diameter_m};
  const auto cells = terrain::summarize(map, foot);
  const std::string counts = std::to_string(cells.known) + " known, " +
                             std::to_string(cells.oblique) + " oblique, " +
                             std::to_string(cells.shadow) + " shadow, " +
                             std::to_string(cells.unknown) + " unknown cells under the foot";
  return {"foothold terrain", cells.known > 0 && cells.known == cells.cells(), counts};
}

}  // namespace

bool InterlockReport::passed() const {
  return std::all_of(checks.begin(), checks.end(), [](const auto& c) { return c.passed; });
}

std::string InterlockReport::firstFailure() const {
  for (const auto& c : checks)
    if (!c.passed) return c.name + ": " + c.detail;
  return {};
}

std::string metres(double value) {
  std::ostringstream s;
  s.precision(3);
  s << std::fixed << value << " m";
  return s.str();
}

std::vector<link::CommandBody> stepCommands(const gait::StepPlan& plan, const gait::Stance& from) {
  std::vector<link::CommandBody> out;
  if (plan.leg >= 0) out.push_back(link::LegMove{plan.leg, plan.recovery.waypoints});
  const gait::BodyPose& a = plan.after_leg.body;
  const gait::BodyPose& b = plan.after.body;
  const Eigen::Vector2d shift = a.toBody(b.xy);
  out.push_back(link::BodyMove{shift.x(), shift.y(), b.heading_rad - a.heading_rad,
                               b.link_z - from.body.link_z});
  return out;
}

InterlockReport checkInterlocks(const gait::StepPlan& plan, const gait::Stance& from,
                                const std::vector<link::CommandBody>& commands,
                                const terrain::ElevationMap& map, const gait::GaitContext& ctx) {
  return {{planned(plan), jointLimits(commands, ctx), reach(plan, ctx), stability(plan, from, ctx),
           footholdTerrain(plan, map, ctx)}};
}

}  // namespace ambler::executive
