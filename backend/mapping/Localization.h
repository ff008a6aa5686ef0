#pragma once

#include <Eigen/Geometry>
#include <optional>

#include "mapping/Registration.h"

namespace ambler::mapping {

// bakambu-csa §2, global localization without a prior on position or
// heading, of a scan into a coarse model (e.g. 1 m heights from orbital
// altimetry), given the scan's tilt from gravity (the rover's
// inclinometers). The levelled scan's height relief is matched against the
// model's in three stages:
//  1. at every heading step, and every shift by a whole or half cell, the
//     scan's cell heights (cells it sees almost wholly) are compared with
//     the model's nodes; the best few placements, apart from each other,
//     go on;
//  2. each is refined over a finer grid of heading and shift, scored on the
//     80 % of cells that agree best (the rest: cells whose hidden part
//     differs from what the scan saw);
//  3. the best refined placement starts registration against the model.
// A placement scores the variance of the height differences (up to one
// common offset) over the scan's own height variance: flat ground fits a
// flat scan anywhere, so a placement counts by how much of the scan's
// relief it explains. Not FPFH with RANSAC: a 1 m model barely samples
// the few features of mostly flat ground, and the descriptors of scan and
// model disagree (docs/mapping.md).
struct GlobalOptions {
  double cell_m = 1.0;        // the model's node spacing
  double yaw_step_deg = 2.0;  // headings tried
  double min_overlap = 0.6;   // of the scan's cells, over model nodes
  // Of a cell's quarter-cell squares, the fraction holding scan points for
  // the cell to be compared with the model.
  double min_cell_coverage = 0.8;
  int candidates = 5;             // placements refined
  double trimmed_fraction = 0.8;  // of the overlap's cells, scored in the refinement
  // Registration against the model, its lengths in model cells.
  RegistrationOptions refine{.voxel_m = 0.2,
                             .source_voxel_m = 0.4,
                             .min_thickness_m = 0.01,
                             .search_heights = false,
                             .search = {},
                             .max_distance_m = 1.5,
                             .min_distance_m = 0.5,
                             .max_iterations = 20,
                             .partner_distance_m = 0.75,
                             .partner_plane_m = 0.1,
                             .agreement_tolerance_m = 0.5,
                             .min_agreement = 0.0,
                             .abandon_agreement = 0.0,
                             .max_rms_m = 0.05,
                             .sigma_floor_m = 0.02,
                             .degenerate_sigma_m = 0.05,
                             .doubtful_sigma_m = 0.01};
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const GlobalOptions& options);

// The rotation of sensor_to_world with its heading about the vertical
// taken out: what an inclinometer tells of the sensor's attitude.
Eigen::Matrix3d withoutYaw(const Eigen::Matrix3d& sensor_to_world);

// `tilt`: the scan frame's rotation to a level frame (withoutYaw); `model`:
// heights on a regular grid of `cell_m` (its phase is taken from the
// points). The result maps the scan into the model's frame, refined by
// registration against the model (whose own convergence and verdict it
// carries); none when no placement overlaps the model enough. Throws
// std::invalid_argument for non-finite points or a scan too small.
std::optional<Registration> localize(const Cloud& scan, const Eigen::Matrix3d& tilt,
                                     const Cloud& model, const GlobalOptions& options = {});

}  // namespace ambler::mapping
