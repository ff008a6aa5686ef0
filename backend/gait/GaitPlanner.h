#pragma once

#include <optional>
#include <vector>

#include "footfall/CostMaps.h"
#include "gait/LegRecovery.h"
#include "gait/Stance.h"
#include "terrain/ElevationMap.h"

namespace ambler::gait {

// The pattern and safety figures of the circulating gait (cmu-1990
// 'Planning strategies', Gaits).
struct GaitOptions {
  double tread_m = 2.25;                 // body axis to the feet (report: walking width 4.5 m)
  double pitch_m = 1.0;                  // foot spacing along the motion (report: 1.5 m)
  double max_body_advance_m = 1.5;       // per body move (report: 1.5 m used, 3.9 m possible)
  double max_body_turn_rad = 0.26;       // per body move (assumed)
  double csp_margin_m = 0.10;            // centre of gravity inside the CSP by at least this
  double execution_slack_m = 0.04;       // kept in hand for the leg due next
  double search_half_m = 0.5;            // half side of the foothold search area around the ideal
  double tread_tolerance_m = 0.25;       // footholds at most this far across the ideal
  double pattern_weight = 0.5;           // composite cost added per metre from the ideal foothold
  double max_stack_span_pitches = 2.25;  // feet of one stack at most this many pitches apart
  double max_stack_lead_pitches = 1.0;   // a new foot at most this far ahead of the other stack
  double body_step_m = 0.02;             // sampling of body moves (radians for point turns)
  int max_candidates_per_leg = 60;       // cells tried, cheapest first, per leg
};

void validate(const GaitOptions& options);

struct GaitContext {
  RoverModel model;
  GaitOptions gait;
  footfall::CostMapOptions footfall;
  RecoveryOptions recovery;
};

// Everything the planner weighed for one leg.
struct LegCandidate {
  int leg = -1;
  Eigen::Vector3d foothold{0, 0, 0};
  double local_advance = 0.0;           // next body move [m or rad]
  double global_advance = 0.0;          // until this foot must recover again [m]
  double support_area = 0.0;            // of the CSP after placement [m^2]
  bool keeps_cycle = false;             // the leg due next can lift after the body move
  double merit = 0.0;                   // normalised product
  double search_widen = 1.0;            // the search region's scale it was found in
  Eigen::Vector2d search_centre{0, 0};  // and its centre (world)
};

// One step: a leg recovery (unless no leg can be lifted) and a body move.
struct StepPlan {
  bool ok = false;
  std::string reason;  // why there is no plan, or what stopped the body
  int leg = -1;        // -1: body move only
  Eigen::Vector3d foothold{0, 0, 0};
  RecoveryPlan recovery;
  double body_u = 0.0;        // along the heading [m, or rad for point turns]
  Stance after_leg;           // feet after the leg move, body before its move
  Stance after;               // after the body move
  double min_csp_margin = 0;  // over the recovery and the body move
  std::vector<LegCandidate> candidates;
  // What the operator sees of the plan: the chosen leg's cost maps (over
  // the region its foothold was searched in) and the body's path, from
  // after_leg to after every body_step_m.
  std::optional<footfall::CostMaps> leg_costs;
  std::vector<BodyPose> body_path;
};

// The footfall module's cost maps for `leg` around its ideal
// circulating-gait foothold, over a search region scaled by `widen`; none
// when that region is off the map.
std::optional<footfall::CostMaps> legCostMaps(const Stance& stance, const Heading& heading,
                                              const terrain::ElevationMap& map,
                                              const GaitContext& context,
                                              const std::optional<footfall::ScannerView>& scanner,
                                              int leg, double widen = 1.0);

// Height field the leg recovery sees: highest z + 2 sigma under the disk,
// NaN if any cell under it is not known.
ClearanceField clearanceFrom(const terrain::ElevationMap& map);

// Plans the next step of the walk along `heading` from `stance` on `map`.
// Legs that may lift keep the centre of gravity in the CSP of the others;
// each places its foot at the cheapest cell of its composite cost map
// (footfall module) near its ideal circulating-gait foothold that keeps
// every constraint; the legs are ranked by local advance x global advance x
// CSP area, normalised; the winner's recovery is planned by A*. The body
// then moves as far as the four constraints allow while some leg can still
// lift at the end.
StepPlan planStep(const Stance& stance, const Heading& heading, const terrain::ElevationMap& map,
                  const GaitContext& context,
                  const std::optional<footfall::ScannerView>& scanner = std::nullopt);

// The step with `leg`'s foot set down at `foothold_xy` (an operator's edit):
// the recovery and body move planStep would make for that placement,
// without its search. Not ok, with the reason, when the leg cannot get
// there; whether the placement is safe is for the interlocks to judge.
StepPlan planStepWithFoothold(const Stance& stance, const Heading& heading,
                              const terrain::ElevationMap& map, const GaitContext& context, int leg,
                              const Eigen::Vector2d& foothold_xy);

// A step planned from `planned_from`, moved onto the stance the rover is
// really in (`actual`, a few centimetres off after slips and execution
// errors): the leg and body moves keep their joint-space and body-frame
// form, so the foot lands where the body's offset takes it. Empty when the
// moved step breaks a constraint (the leg may not lift, the placement or
// any point of the body move fails) and must be replanned.
std::optional<StepPlan> reanchorStep(const StepPlan& plan, const Stance& planned_from,
                                     const Stance& actual, const Heading& heading,
                                     const GaitContext& context);

// The link-plane height for a stance: nominal above the mean foot, inside
// every leg's vertical range.
double linkHeightFor(const Stance& stance, const RoverModel& model);

// A stance in the gait's regular pattern around `body`, feet on `ground_z`.
Stance nominalStance(const BodyPose& body, const RoverModel& model, const GaitOptions& gait);

}  // namespace ambler::gait
