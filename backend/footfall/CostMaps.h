#pragma once

#include <Eigen/Core>
#include <optional>

#include "footfall/Criteria.h"

namespace ambler::footfall {

// Where the leg is and what it looks for, at the moment it is recovered.
struct ScannerView {
  Eigen::Vector2d position{0.0, 0.0};  // on the ground plane [m]
  double heading_rad = 0.0;            // of the optical axis
  double horizontal_fov_rad = 1.047;
};

struct LegContext {
  Eigen::Vector2d shaft{0.0, 0.0};     // the leg's vertical shaft on the ground plane [m]
  double heading_rad = M_PI / 2;       // direction of the next body move
  double reference_z = 0.0;            // ground height the elevation limits are relative to [m]
  std::optional<ScannerView> scanner;  // without one, no visibility cost
};

// cmu-1990 'Footfalls', Table 1: discrete constraints a foothold must meet.
struct CostLimits {
  double reach_min_m = 1.0;  // horizontal distance from the shaft
  double reach_max_m = 2.5;
  double elevation_min_m = -1.0;  // where the foot touches, relative to reference_z
  double elevation_max_m = 1.0;
};

// Weights of the continuous costs, each of them in [0, 1].
struct CostWeights {
  double roughness = 1.0;
  double slope = 0.5;
  double body_advance = 1.0;
  double visibility = 0.3;
};

struct CostMapOptions {
  FootOptions foot;
  CostLimits limits;
  CostWeights weights;
  Criterion roughness_criterion = Criterion::kEquilibrium;
  double roughness_scale = 0.002;   // criterion score that costs 1 [its unit]
  double max_body_advance_m = 1.5;  // the planner's advance threshold (cmu-1990: 1.5 m)
};

// Throws std::invalid_argument naming the first field out of range.
void validate(const CostMapOptions& options);

// The constraint cost maps of the gait planner and their weighted sum. Each
// continuous cost is in [0, 1]; the composite is NaN where a discrete
// constraint fails or the foot cannot stand, so its minimum is the planned
// foothold.
struct CostMaps {
  ScoreMap roughness;     // criterion score / scale, capped at 1
  ScoreMap slope;         // plane tilt / max tilt, capped at 1
  ScoreMap body_advance;  // 1 - advance / max advance
  ScoreMap visibility;    // share of the leg's horizontal link in the scanner's view
  ScoreMap composite;
};

CostMaps buildCostMaps(const terrain::ElevationMap& map, const Box2& region, const LegContext& leg,
                       const CostMapOptions& options = {});

// How far the body can move along the heading with the foot at `foot`
// before the foot leaves the leg's reach [m], capped at `max_advance`.
double bodyAdvance(const Eigen::Vector2d& foot, const LegContext& leg, double reach_max,
                   double max_advance);
// The same with the shaft's unit direction of motion given.
double bodyAdvance(const Eigen::Vector2d& foot, const Eigen::Vector2d& shaft,
                   const Eigen::Vector2d& direction, double reach_max, double max_advance);

// Share of the segment from the shaft to the foot that lies inside the
// scanner's horizontal field of view, in [0, 1] (exact: the view is a
// wedge, or the complement of one).
double linkInView(const Eigen::Vector2d& foot, const Eigen::Vector2d& shaft,
                  const ScannerView& scanner);

}  // namespace ambler::footfall
