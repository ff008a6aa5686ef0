#include "gait/GaitPlanner.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "core/Region.h"
#include "footfall/Footprint.h"
#include "terrain/Queries.h"

namespace ambler::gait {

namespace {

// How far `world` lies from leg's shaft along the motion there (body frame).
double alongMotion(const Stance& stance, const Heading& heading, const RoverModel& model, int leg,
                   const Eigen::Vector2d& world) {
  const Eigen::Vector2d shaft = model.shaftOf(leg);
  return (stance.body.toBody(world) - shaft).dot(heading.motionAt(shaft));
}

// The foremost foot of `shaft`'s stack along its motion, leaving `except`
// out (-INFINITY when no other foot is on that shaft).
double stackFront(const Stance& stance, const Heading& heading, const RoverModel& model, int shaft,
                  int except) {
  double front = -INFINITY;
  for (int i = 0; i < kLegCount; ++i)
    if (i != except && model.shaft_of_leg[std::size_t(i)] == shaft)
      front = std::max(
          front, alongMotion(stance, heading, model, i, stance.feet[std::size_t(i)].head<2>()));
  return front;
}

// Where the circulating gait wants leg's foot (world): one pitch
// beyond the foremost foot of its stack along the motion at its shaft, at
// the tread, pulled in to stay 0.1 m inside the reach.
Eigen::Vector2d idealFoothold(const Stance& stance, const Heading& heading, const RoverModel& model,
                              const GaitOptions& gait, int leg) {
  const Eigen::Vector2d shaft = model.shaftOf(leg);
  const Eigen::Vector2d d = heading.motionAt(shaft);
  Eigen::Vector2d out(d.y(), -d.x());
  if (out.dot(shaft) < 0) out = -out;
  const double front =
      stackFront(stance, heading, model, model.shaft_of_leg[std::size_t(leg)], leg);
  const double lateral = gait.tread_m - std::abs(shaft.x());
  const double reach = model.extension_max_m - 0.1;
  const double along_max = std::sqrt(std::max(reach * reach - lateral * lateral, 0.0));
  const double along = std::min(front + gait.pitch_m, along_max);
  return stance.body.toWorld(Eigen::Vector2d(shaft + along * d + lateral * out));
}

// Pattern constraint: how far apart, along the motion `d` (body frame), the
// feet of leg's stack stand. A stack spread much over two pitches cannot
// lift its rear foot before that foot reaches its kinematic limit.
double stackSpan(const Stance& stance, const RoverModel& m, int leg, const Eigen::Vector2d& d) {
  double lo = INFINITY, hi = -INFINITY;
  for (int i = 0; i < kLegCount; ++i) {
    if (m.shaft_of_leg[std::size_t(i)] != m.shaft_of_leg[std::size_t(leg)]) continue;
    const double a =
        stance.body.toBody(Eigen::Vector2d(stance.feet[std::size_t(i)].head<2>())).dot(d);
    lo = std::min(lo, a);
    hi = std::max(hi, a);
  }
  return hi - lo;
}

// How far `xy` (world), as leg's foot, would lead the other stack's
// foremost foot, each along its own stack's motion.
double leadOverOtherStack(const Stance& stance, const Heading& heading, const RoverModel& m,
                          int leg, const Eigen::Vector2d& xy) {
  const int other = 1 - m.shaft_of_leg[std::size_t(leg)];
  return alongMotion(stance, heading, m, leg, xy) - stackFront(stance, heading, m, other, -1);
}

double headingAngle(const BodyPose& body, const Eigen::Vector2d& body_direction) {
  const Eigen::Vector2d w = body.rotation() * body_direction;
  return std::atan2(w.y(), w.x());
}

double soleHeight(const terrain::ElevationMap& map, const Eigen::Vector2d& xy, double radius) {
  return terrain::summarize(map, Disk{xy, radius}).max_z;
}

double uMax(const Heading& heading, const GaitOptions& g) {
  const double w = std::abs(heading.turnPerUnit());
  if (heading.isPointTurn()) return g.max_body_turn_rad;
  return w > 0 ? std::min(g.max_body_advance_m, g.max_body_turn_rad / w) : g.max_body_advance_m;
}

// The supporting leg with the least travel left before its reach stops
// the body: the one that must recover next.
int nextToRecover(const Stance& stance, const Heading& heading, const RoverModel& m) {
  int worst = -1;
  double least = INFINITY;
  // Called for every sampled body move of every candidate: one rotation,
  // and unit directions without an angle in between.
  const Eigen::Matrix2d rotation = stance.body.rotation();
  for (int i = 0; i < kLegCount; ++i) {
    if (!stance.supporting[std::size_t(i)]) continue;
    const Eigen::Vector2d shaft = stance.body.xy + rotation * m.shaftOf(i);
    const Eigen::Vector2d motion = rotation * heading.motionAt(m.shaftOf(i));
    const double norm = motion.norm();
    const Eigen::Vector2d direction =
        norm > 0 ? Eigen::Vector2d(motion / norm) : Eigen::Vector2d::UnitX();
    const double left = footfall::bodyAdvance(stance.feet[std::size_t(i)].head<2>(), shaft,
                                              direction, m.extension_max_m, 10.0);
    if (left < least) least = left, worst = i;
  }
  return worst;
}

// The largest body move (within the options' caps) after which some leg
// may lift, and what stopped it; u is negative when there is none, not even
// at u = 0.
struct FreeMove : BodyMoveLimit {
  bool next_can_lift = false;  // the leg due next, not just some leg
};

FreeMove bodyMoveKeepingALegFree(const Stance& stance, const Heading& heading,
                                 const GaitContext& ctx) {
  const auto& g = ctx.gait;
  FreeMove limit{
      maxBodyMove(stance, heading, ctx.model, g.csp_margin_m, uMax(heading, g), g.body_step_m)};
  // With slack: execution and dead-reckoning errors of a few centimetres
  // must not take the next leg's margin below the limit.
  const double margin = g.csp_margin_m + g.execution_slack_m;
  const auto canLift = [&](const Stance& s, int leg) {
    return leg >= 0 && s.supporting[std::size_t(leg)] && marginWithout(s, ctx.model, leg) >= margin;
  };
  // Prefer to stop where the leg that must recover next can lift; else
  // where any leg can (the farthest such move, found on the same pass).
  std::optional<double> any_leg;
  for (double u = limit.u; u > -1e-9; u -= g.body_step_m) {
    const Stance moved = moveBody(stance, heading, std::max(u, 0.0));
    if (canLift(moved, nextToRecover(moved, heading, ctx.model))) {
      limit.u = std::max(u, 0.0);
      limit.next_can_lift = true;
      return limit;
    }
    for (int leg = 0; !any_leg && leg < kLegCount; ++leg)
      if (canLift(moved, leg)) any_leg = std::max(u, 0.0);
  }
  limit.u = any_leg.value_or(-1.0);
  return limit;
}

footfall::LegContext legContext(const Stance& stance, const Heading& heading, const RoverModel& m,
                                int leg, const std::optional<footfall::ScannerView>& scanner) {
  footfall::LegContext lc;
  lc.shaft = stance.body.toWorld(m.shaftOf(leg));
  lc.heading_rad = headingAngle(stance.body, heading.motionAt(m.shaftOf(leg)));
  lc.reference_z = stance.body.link_z - m.link_plane_nominal_m;
  lc.scanner = scanner;
  return lc;
}

// The body's pose every `step` along its move of `u` from `start`.
std::vector<BodyPose> bodyPath(const Stance& start, const Heading& heading, double u, double step) {
  std::vector<BodyPose> path{start.body};
  for (double s = step; s < u + step; s += step)
    path.push_back(moveBody(start, heading, std::min(s, u)).body);
  return path;
}

// The footfall module's cost maps for `leg` over a square of half side
// search_half_m x widen around `centre` (world); none off the map.
std::optional<footfall::CostMaps> costMapsAround(
    const Stance& stance, const Heading& heading, const terrain::ElevationMap& map,
    const GaitContext& ctx, const std::optional<footfall::ScannerView>& scanner, int leg,
    const Eigen::Vector2d& centre, double widen) {
  const RoverModel& m = ctx.model;
  const double h = ctx.gait.search_half_m * widen;
  const Box2 region{centre.x() - h, centre.y() - h, centre.x() + h, centre.y() + h};
  const Box2 bounds = map.grid().bounds();
  const Box2 clipped{std::max(region.x_min, bounds.x_min), std::max(region.y_min, bounds.y_min),
                     std::min(region.x_max, bounds.x_max), std::min(region.y_max, bounds.y_max)};
  // Off the map, or on it by less than half a cell.
  if (!footfall::holdsCellCentre(map.grid(), clipped)) return std::nullopt;
  footfall::CostMapOptions fo = ctx.footfall;
  fo.limits.reach_max_m = std::min(fo.limits.reach_max_m, m.extension_max_m);
  fo.limits.reach_min_m = std::max(fo.limits.reach_min_m, m.extension_min_m);
  return footfall::buildCostMaps(map, clipped, legContext(stance, heading, m, leg, scanner), fo);
}

// Whether `leg`'s foot at `xy` would stand nearer than `separation` to
// another supporting foot.
bool crowds(const Stance& stance, int leg, const Eigen::Vector2d& xy, double separation) {
  for (int j = 0; j < kLegCount; ++j)
    if (j != leg && stance.supporting[std::size_t(j)] &&
        (stance.feet[std::size_t(j)].head<2>() - xy).norm() < separation)
      return true;
  return false;
}

// Tries the cheapest cells of leg's composite cost map around `centre`
// (among equals, nearest it) until one keeps every constraint and leaves a
// body move after which a leg can lift.
std::optional<LegCandidate> candidateFor(const Stance& stance, const Heading& heading,
                                         const terrain::ElevationMap& map, const GaitContext& ctx,
                                         const std::optional<footfall::ScannerView>& scanner,
                                         int leg, const Eigen::Vector2d& centre, double widen) {
  const RoverModel& m = ctx.model;
  const Eigen::Vector2d d = heading.motionAt(m.shaftOf(leg));
  const Eigen::Vector2d lateral = stance.body.rotation() * Eigen::Vector2d(d.y(), -d.x());
  const auto costs = costMapsAround(stance, heading, map, ctx, scanner, leg, centre, widen);
  if (!costs) return std::nullopt;
  const footfall::CostMaps& maps = *costs;
  const footfall::LegContext lc = legContext(stance, heading, m, leg, scanner);

  // Cheapest first; among equals, nearest the centre: the pattern's
  // foothold (a foot placed too far ahead would leave the rear leg unable to
  // lift later), or where a shuffled foot stands.
  const auto& score = maps.composite.score;
  const GridSpec& g = maps.composite.grid;
  std::vector<std::pair<double, int>> order;
  for (int i = 0; i < int(score.size()); ++i)
    if (std::isfinite(score.data()[i]))
      order.push_back({score.data()[i] + ctx.gait.pattern_weight *
                                             (g.cellCenter(i / g.cols, i % g.cols) - centre).norm(),
                       i});
  std::sort(order.begin(), order.end());
  // The cheapest cell that keeps every constraint, preferring one after
  // which the leg due next can still lift (else the walk may dead-end).
  std::optional<LegCandidate> fallback;
  const int tries =
      std::min<int>(int(order.size()), int(ctx.gait.max_candidates_per_leg * widen * widen));
  for (int k = 0; k < tries; ++k) {
    const int cell = order[std::size_t(k)].second;
    const Eigen::Vector2d xy = g.cellCenter(cell / g.cols, cell % g.cols);
    // Setting a foot down where it stood is no step.
    if ((xy - stance.feet[std::size_t(leg)].head<2>()).norm() < ctx.gait.pitch_m / 4) continue;
    // Keep the tread: the stance's CSP depends on it more than on the pitch.
    if (std::abs((xy - centre).dot(lateral)) > ctx.gait.tread_tolerance_m * widen) continue;
    // A foot set down at the bare separation from another ends within it
    // after the few millimetres of a touch-down error, and then no stance
    // holding both passes the check until one of them lifts.
    if (crowds(stance, leg, xy, m.min_leg_separation_m + ctx.gait.execution_slack_m)) continue;
    const double z = soleHeight(map, xy, 0.5 * m.foot_diameter_m);
    if (!std::isfinite(z)) continue;
    Stance placed = stance;
    placed.feet[std::size_t(leg)] = {xy.x(), xy.y(), z};
    // Widened searches step over obstacles, so they may stretch the stack.
    const double span = ctx.gait.max_stack_span_pitches * ctx.gait.pitch_m + 0.4 * (widen - 1.0);
    if (stackSpan(placed, m, leg, d) > span) continue;
    // Not in point turns, where the stacks move in opposite directions.
    if (!heading.isPointTurn() &&
        leadOverOtherStack(stance, heading, m, leg, xy) >
            ctx.gait.max_stack_lead_pitches * ctx.gait.pitch_m + 0.4 * (widen - 1.0))
      continue;
    if (!checkStance(placed, stance, m, ctx.gait.csp_margin_m).ok()) continue;
    Stance raised = placed;
    raised.body.link_z = linkHeightFor(placed, m);
    if (!checkStance(raised, stance, m, ctx.gait.csp_margin_m).ok()) continue;
    const FreeMove next = bodyMoveKeepingALegFree(raised, heading, ctx);
    // A placement that frees no advance is still worth it when it lets the
    // leg that blocks the body lift next (a shuffle step).
    const auto freed = liftableLegs(raised, m, ctx.gait.csp_margin_m);
    const bool unblocks = next.leg >= 0 && next.leg != leg &&
                          std::find(freed.begin(), freed.end(), next.leg) != freed.end();
    if (next.u < 0.0 || (next.u < ctx.gait.body_step_m && !unblocks)) continue;
    LegCandidate c;
    c.leg = leg;
    c.foothold = placed.feet[std::size_t(leg)];
    c.local_advance = std::max(next.u, ctx.gait.body_step_m);
    c.keeps_cycle = next.next_can_lift;
    c.global_advance = footfall::bodyAdvance(xy, lc, m.extension_max_m, 10.0);
    c.support_area = area(conservativeSupportPolygon(raised.supportingFeet()));
    c.search_widen = widen;
    c.search_centre = centre;
    if (c.keeps_cycle) return c;
    if (!fallback) fallback = c;
  }
  return fallback;
}

}  // namespace

std::optional<footfall::CostMaps> legCostMaps(const Stance& stance, const Heading& heading,
                                              const terrain::ElevationMap& map,
                                              const GaitContext& ctx,
                                              const std::optional<footfall::ScannerView>& scanner,
                                              int leg, double widen) {
  const Eigen::Vector2d ideal = idealFoothold(stance, heading, ctx.model, ctx.gait, leg);
  return costMapsAround(stance, heading, map, ctx, scanner, leg, ideal, widen);
}

void validate(const GaitOptions& g) {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(what);
  };
  require(g.tread_m > 0 && g.tread_m < 20, "gait.tread_m must be in (0, 20)");
  require(g.pitch_m > 0 && g.pitch_m < 10, "gait.pitch_m must be in (0, 10)");
  require(g.max_body_advance_m > 0 && g.max_body_advance_m <= 3.9,
          "gait.max_body_advance_m must be in (0, 3.9] (the Ambler's maximum body advance)");
  require(g.max_body_turn_rad > 0 && g.max_body_turn_rad <= M_PI / 2,
          "gait.max_body_turn_deg must be in (0, 90]");
  require(g.csp_margin_m >= 0 && g.csp_margin_m < 2, "gait.csp_margin_m must be in [0, 2)");
  require(g.execution_slack_m >= 0 && g.execution_slack_m < 1,
          "gait.execution_slack_m must be in [0, 1)");
  require(g.search_half_m > 0 && g.search_half_m <= 3, "gait.search_half_m must be in (0, 3]");
  require(g.tread_tolerance_m > 0 && g.tread_tolerance_m <= 3,
          "gait.tread_tolerance_m must be in (0, 3]");
  require(g.pattern_weight >= 0 && g.pattern_weight <= 100,
          "gait.pattern_weight must be in [0, 100]");
  require(g.max_stack_span_pitches >= 2 && g.max_stack_span_pitches <= 10,
          "gait.max_stack_span_pitches must be in [2, 10]");
  require(g.max_stack_lead_pitches >= 0.5 && g.max_stack_lead_pitches <= 10,
          "gait.max_stack_lead_pitches must be in [0.5, 10]");
  require(g.body_step_m > 0 && g.body_step_m <= 0.5, "gait.body_step_m must be in (0, 0.5]");
  require(g.max_candidates_per_leg >= 1, "gait.max_candidates_per_leg must be >= 1");
}

ClearanceField clearanceFrom(const terrain::ElevationMap& map) {
  return [&map](const Eigen::Vector2d& xy, double radius) {
    double top = -INFINITY;
    bool unknown = false;
    forEachCellIn(map.grid(), Disk{xy, radius}, [&](int r, int c) {
      if (!map.hasHeight(r, c))
        unknown = true;
      else
        top = std::max(top, double(map.elevation(r, c)) + 2.0 * double(map.sigma(r, c)));
    });
    return unknown || !std::isfinite(top) ? NAN : top;
  };
}

double linkHeightFor(const Stance& stance, const RoverModel& m) {
  double lo = -INFINITY, hi = INFINITY, sum = 0.0;
  int n = 0;
  for (int i = 0; i < kLegCount; ++i) {
    if (!stance.supporting[std::size_t(i)]) continue;
    const double z = stance.feet[std::size_t(i)].z();
    lo = std::max(lo, z + m.vertical_min_m + 0.2);
    hi = std::min(hi, z + m.vertical_max_m - 0.2);
    sum += z;
    ++n;
  }
  const double want = sum / std::max(n, 1) + m.link_plane_nominal_m;
  return lo <= hi ? std::clamp(want, lo, hi) : want;
}

namespace {

// Every liftable leg's best placement: around the ideal footholds first;
// where obstacles or unknown ground leave nothing there, over wider areas
// (2x, 3x) before giving up; where nothing ahead lets the leg due next lift
// after it, a shuffle (below). Ranked by the normalised product of local
// advance, global advance and CSP area (cmu-1990 'Planning strategies',
// fig. 8); a placement after which the leg due next cannot lift only wins
// when nothing else is possible.
std::vector<LegCandidate> rankedCandidates(const Stance& stance, const Heading& heading,
                                           const terrain::ElevationMap& map, const GaitContext& ctx,
                                           const std::optional<footfall::ScannerView>& scanner,
                                           double max_widen = 3.0, bool shuffle = true) {
  std::vector<LegCandidate> out;
  const auto legs = liftableLegs(stance, ctx.model, ctx.gait.csp_margin_m);
  const auto keepsCycle = [&out] {
    return std::any_of(out.begin(), out.end(), [](const auto& c) { return c.keeps_cycle; });
  };
  for (double widen = 1.0; widen <= max_widen && !keepsCycle(); widen += 1.0)
    for (int leg : legs) {
      const Eigen::Vector2d ideal = idealFoothold(stance, heading, ctx.model, ctx.gait, leg);
      if (auto c = candidateFor(stance, heading, map, ctx, scanner, leg, ideal, widen))
        out.push_back(*c);
    }
  // A rear foot trails so far that the middle feet cannot hold the body
  // without it, and every placement ahead leaves it so: a shuffle sets a
  // foot down near where it stands, backward too, so that the trailing leg
  // may lift next.
  if (shuffle && !keepsCycle())
    for (int leg : legs) {
      const Eigen::Vector2d here = stance.feet[std::size_t(leg)].head<2>();
      if (auto c = candidateFor(stance, heading, map, ctx, scanner, leg, here, 2.0))
        if (c->keeps_cycle) out.push_back(*c);
    }
  double top_local = 0, top_global = 0, top_area = 0;
  for (const auto& c : out) {
    top_local = std::max(top_local, c.local_advance);
    top_global = std::max(top_global, c.global_advance);
    top_area = std::max(top_area, c.support_area);
  }
  for (auto& c : out)
    c.merit = (c.local_advance / top_local) * (c.global_advance / std::max(top_global, 1e-9)) *
              (c.support_area / std::max(top_area, 1e-9)) * (c.keeps_cycle ? 1.0 : 0.01);
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.merit > b.merit; });
  return out;
}

// The stance after placing `c` and moving the body as the step would.
Stance afterStep(const Stance& stance, const LegCandidate& c, const Heading& heading,
                 const GaitContext& ctx) {
  Stance placed = stance;
  placed.feet[std::size_t(c.leg)] = c.foothold;
  placed.body.link_z = linkHeightFor(placed, ctx.model);
  return moveBody(placed, heading, std::max(0.0, bodyMoveKeepingALegFree(placed, heading, ctx).u));
}

// One step of lookahead: candidates whose following step still has a
// placement that keeps the cycle go first (the gait is otherwise greedy and
// can walk into a stance where no leg may lift).
void preferOpenFutures(std::vector<LegCandidate>& ranked, const Stance& stance,
                       const Heading& heading, const terrain::ElevationMap& map,
                       const GaitContext& ctx) {
  std::stable_partition(ranked.begin(), ranked.end(), [&](const LegCandidate& c) {
    // Around the ideal footholds only, no shuffles: enough to see a dead
    // end coming (a future that needs a shuffle is one), and it keeps a
    // step's planning time even.
    const auto next =
        rankedCandidates(afterStep(stance, c, heading, ctx), heading, map, ctx, {}, 2.0, false);
    return std::any_of(next.begin(), next.end(), [](const auto& n) { return n.keeps_cycle; });
  });
}

// When no leg may lift and moving along the heading does not help (a point
// turn rotates the feet about the centre of gravity, leaving every margin
// as it was), the shortest straight body shift after which a leg may lift
// and has a foothold to go to; a shift that frees a leg with nowhere to go
// only leads to the next shift.
std::optional<Stance> shiftToFreeALeg(const Stance& stance, const Heading& heading,
                                      const terrain::ElevationMap& map, const GaitContext& ctx) {
  const auto& g = ctx.gait;
  const auto& m = ctx.model;
  for (double distance = g.body_step_m; distance <= 0.6 + 1e-9; distance += g.body_step_m)
    for (int k = 0; k < 16; ++k) {
      const Eigen::Vector2d dir(std::cos(k * M_PI / 8), std::sin(k * M_PI / 8));
      bool clear = true;
      Stance moved = stance;
      for (double t = g.body_step_m; clear && t <= distance + 1e-9; t += g.body_step_m) {
        moved.body.xy = stance.body.xy + std::min(t, distance) * dir;
        // From `stance`: a foot a slip left beyond its leg's reach may stay
        // beyond it on the way, as long as the shift brings it closer.
        clear = checkStance(moved, stance, m, g.csp_margin_m).ok();
      }
      if (clear && !liftableLegs(moved, ctx.model, g.csp_margin_m + g.execution_slack_m).empty() &&
          !rankedCandidates(moved, heading, map, ctx, {}, 2.0).empty())
        return moved;
    }
  return std::nullopt;
}

}  // namespace

StepPlan planStep(const Stance& stance, const Heading& heading, const terrain::ElevationMap& map,
                  const GaitContext& ctx, const std::optional<footfall::ScannerView>& scanner) {
  StepPlan plan;
  const auto& m = ctx.model;
  plan.candidates = rankedCandidates(stance, heading, map, ctx, scanner);
  std::vector<LegCandidate> ranked = plan.candidates;
  preferOpenFutures(ranked, stance, heading, map, ctx);

  Stance placed = stance;
  for (const auto& c : ranked) {
    RecoveryPlan r =
        planLegRecovery(m, stance, c.leg, c.foothold, clearanceFrom(map), ctx.recovery);
    if (!r.found) continue;
    plan.leg = c.leg;
    plan.foothold = c.foothold;
    plan.recovery = std::move(r);
    plan.leg_costs =
        costMapsAround(stance, heading, map, ctx, scanner, c.leg, c.search_centre, c.search_widen);
    placed.feet[std::size_t(c.leg)] = c.foothold;
    plan.min_csp_margin = marginWithout(stance, m, c.leg);
    break;
  }
  placed.body.link_z = linkHeightFor(placed, m);
  plan.after_leg = placed;
  const FreeMove move = bodyMoveKeepingALegFree(placed, heading, ctx);
  const double u = move.u;
  const Constraint stopped = move.stopped_by;
  if (u < ctx.gait.body_step_m && plan.leg < 0) {
    if (auto shifted = shiftToFreeALeg(stance, heading, map, ctx)) {
      plan.after = *shifted;
      plan.body_path = {stance.body, shifted->body};
      plan.reason = "body shifted to free a leg";
      plan.min_csp_margin = std::min(checkStance(stance, stance, m, 0.0).csp_margin_m,
                                     checkStance(*shifted, stance, m, 0.0).csp_margin_m);
      plan.ok = true;
      return plan;
    }
    plan.reason = plan.candidates.empty() ? "no leg can lift and reach a known, stable foothold"
                                          : "no collision-free leg recovery";
    return plan;
  }
  plan.body_u = std::max(u, 0.0);
  plan.after = moveBody(placed, heading, plan.body_u);
  plan.body_path = bodyPath(placed, heading, plan.body_u, ctx.gait.body_step_m);
  plan.reason = "body stopped by " + constraintName(stopped);
  const double margin_after = checkStance(plan.after, stance, m, 0.0).csp_margin_m;
  const double margin_placed = checkStance(placed, stance, m, 0.0).csp_margin_m;
  plan.min_csp_margin = plan.leg < 0 ? std::min(margin_placed, margin_after)
                                     : std::min({plan.min_csp_margin, margin_placed, margin_after});
  plan.ok = true;
  return plan;
}

StepPlan planStepWithFoothold(const Stance& stance, const Heading& heading,
                              const terrain::ElevationMap& map, const GaitContext& ctx, int leg,
                              const Eigen::Vector2d& foothold_xy) {
  const auto& m = ctx.model;
  StepPlan plan;
  plan.leg = leg;
  // Where the map knows no ground the foot is assumed level with where it
  // stands; the foothold-terrain interlock refuses such a step anyway.
  double z = soleHeight(map, foothold_xy, 0.5 * m.foot_diameter_m);
  if (!std::isfinite(z)) z = stance.feet[std::size_t(leg)].z();
  plan.foothold = {foothold_xy.x(), foothold_xy.y(), z};
  Stance placed = stance;
  placed.feet[std::size_t(leg)] = plan.foothold;
  placed.body.link_z = linkHeightFor(placed, m);
  plan.after_leg = plan.after = placed;
  plan.min_csp_margin =
      std::min(marginWithout(stance, m, leg), checkStance(placed, stance, m, 0.0).csp_margin_m);
  plan.recovery = planLegRecovery(m, stance, leg, plan.foothold, clearanceFrom(map), ctx.recovery);
  plan.leg_costs = legCostMaps(stance, heading, map, ctx, std::nullopt, leg);
  plan.body_path = {placed.body};
  if (!plan.recovery.found) {
    plan.reason = "no collision-free leg recovery to that foothold";
    return plan;
  }
  const FreeMove move = bodyMoveKeepingALegFree(placed, heading, ctx);
  plan.body_u = std::max(move.u, 0.0);
  plan.after = moveBody(placed, heading, plan.body_u);
  plan.body_path = bodyPath(placed, heading, plan.body_u, ctx.gait.body_step_m);
  plan.min_csp_margin =
      std::min(plan.min_csp_margin, checkStance(plan.after, stance, m, 0.0).csp_margin_m);
  plan.reason = move.u < 0 ? "no leg could lift after any body move"
                           : "body stopped by " + constraintName(move.stopped_by);
  plan.ok = true;
  return plan;
}

std::optional<StepPlan> reanchorStep(const StepPlan& plan, const Stance& planned_from,
                                     const Stance& actual, const Heading& heading,
                                     const GaitContext& ctx) {
  const auto& m = ctx.model;
  const double margin = ctx.gait.csp_margin_m;
  if (plan.leg < 0) return std::nullopt;  // a body-only step is cheap to plan again
  if (marginWithout(actual, m, plan.leg) < margin) return std::nullopt;
  StepPlan moved = plan;
  moved.foothold = actual.body.toWorld(planned_from.body.toBody(plan.foothold));
  moved.foothold.z() = plan.foothold.z();
  Stance placed = actual;
  placed.feet[std::size_t(plan.leg)] = moved.foothold;
  if (!checkStance(placed, actual, m, margin).ok()) return std::nullopt;
  placed.body.link_z = plan.after_leg.body.link_z;
  if (!checkStance(placed, actual, m, margin).ok()) return std::nullopt;
  // The body move is derived again on the real stance, so that the leg due
  // next can still lift after it (it may come out a little shorter).
  const FreeMove body = bodyMoveKeepingALegFree(placed, heading, ctx);
  if (body.u < ctx.gait.body_step_m || !body.next_can_lift) return std::nullopt;
  moved.body_u = body.u;
  moved.after_leg = placed;
  moved.after = moveBody(placed, heading, body.u);
  moved.body_path = bodyPath(placed, heading, body.u, ctx.gait.body_step_m);
  return moved;
}

Stance nominalStance(const BodyPose& body, const RoverModel& m, const GaitOptions& g) {
  Stance s;
  s.body = body;
  // Staggered stacks so the centre of gravity sits in the CSP: the left
  // stack at -1.25, -0.25, 0.75 pitches, the right at -0.75, 0.25, 1.25.
  // (One 2-D table: GCC 12 with -fsanitize=undefined miscompiles indexing
  // `(cond ? left : right)[i]`: every right-hand foot got the first pitch.)
  static constexpr double kPitches[2][3] = {{-1.25, -0.25, 0.75}, {-0.75, 0.25, 1.25}};
  for (int i = 0; i < kLegCount; ++i) {
    const bool is_left = m.shaft_of_leg[std::size_t(i)] == 0;
    const double along = kPitches[is_left ? 0 : 1][i % 3] * g.pitch_m;
    const Eigen::Vector2d foot =
        body.toWorld(Eigen::Vector2d(is_left ? -g.tread_m : g.tread_m, along));
    s.feet[std::size_t(i)] = {foot.x(), foot.y(), body.link_z - m.link_plane_nominal_m};
  }
  return s;
}

}  // namespace ambler::gait
