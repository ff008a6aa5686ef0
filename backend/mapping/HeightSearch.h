#pragma once

#include <Eigen/Geometry>
#include <vector>

namespace ambler::mapping {

// The coarse stage of registration: both clouds as heights over the plane
// of a working frame whose z is across the ground (the target's principal
// frame), and an exhaustive search over shifts and turns about z near the
// guess, each placement scored on the height differences left after the
// best common tilt and offset, truncated so that what one view saw and the
// other did not (shadows, a rock's far side) counts as a fixed penalty. It
// is what brings GICP into its basin when the guess is off by tenths of a
// metre and degrees of heading: ICP alone crawls along ground that holds
// it only loosely, and noise pulls it aside on the way (docs/mapping.md).
struct HeightSearchOptions {
  double cell_m = 0.2;        // of the height grids
  double max_shift_m = 0.4;   // searched each way along x and y
  double max_turn_deg = 4.0;  // searched each way about z
  double truncation_m = 0.1;  // height differences count up to this
};

// The motion of `source` (working frame, already placed by the guess) that
// best matches `target`'s heights; the identity when the clouds share too
// few cells to judge.
Eigen::Isometry3d searchHeights(const std::vector<Eigen::Vector3d>& source,
                                const std::vector<Eigen::Vector3d>& target,
                                const HeightSearchOptions& options = {});

// The share of `source`'s cells over known target heights whose height is
// within `tolerance_m` of the target's: near 1 where the two clouds are of
// the same ground and registered, low for clouds of different ground
// however they are placed. NaN when no cell is over the target.
double heightAgreement(const std::vector<Eigen::Vector3d>& source,
                       const std::vector<Eigen::Vector3d>& target, double cell_m,
                       double tolerance_m);

}  // namespace ambler::mapping
