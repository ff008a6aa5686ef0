#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "mapping/HeightSearch.h"

namespace ambler::mapping {

using Cloud = std::vector<Eigen::Vector3d>;

// Every point of `cloud` moved by `motion`.
Cloud transformed(const Cloud& cloud, const Eigen::Isometry3d& motion);

// Registration of two scans of the ground (bakambu-csa §2): a search over
// heights brings the source within centimetres, then generalized ICP
// (Segal, Haehnel & Thrun 2009, plane-to-plane) finishes, on a sparser
// source first and then on every thinned point, each pair weighted by a
// Geman-McClure kernel on its Mahalanobis distance. The work is done in a
// frame set by the target itself (its centroid and principal axes), so the
// result does not depend on the frame the clouds come in.
struct RegistrationOptions {
  // A cloud whose scanner is known is first thinned to voxel means this
  // size and each moved along its ray onto the plane of the points around
  // it (the smallest block of hashed cells holding ray_neighbours of them):
  // a rangefinder's noise lies along the ray, so the point's true place is
  // on it (ScannerOrigins).
  double ray_voxel_m = 0.05;
  int ray_neighbours = 45;         // 0: the points stay where the scan put them
  double voxel_m = 0.1;            // thinning of both clouds: one mean point per voxel
  double source_voxel_m = 0.2;     // of those, one per voxel this size is moved first
  int neighbours = 20;             // of a point, for its covariance
  double min_thickness_m = 0.001;  // a covariance's standard deviation across the surface
  // A search over heights (HeightSearch.h) first: for terrain scans, off
  // for clouds whose z is not across the ground or too sparse to grid.
  bool search_heights = true;
  HeightSearchOptions search;
  double max_distance_m = 0.3;  // pairing distance of the first stage; halved per stage
  double min_distance_m = 0.3;  // of the last stage
  double kernel_sigmas = 3.0;   // Geman-McClure scale, in Mahalanobis distance
  int max_iterations = 60;      // over all stages, for each of the two passes
  double min_step = 1e-4;       // [m; rad x 10]: a smaller update ends the last stage
  int threads = 0;              // 0: all the machine's cores
  // The verdict's limits (RegistrationQuality).
  double partner_distance_m = 0.15;  // a source point with a target point this near
  double partner_plane_m = 0.03;     // and this near its surface has a partner
  double min_overlap = 0.15;         // of source points with a partner, below: no overlap
  double trusted_overlap = 0.5;      // below: doubtful
  // Of the source's height cells over the target's, the share within the
  // tolerance of the target's heights: clouds of different ground stay
  // below the minimum however they are placed (no overlap).
  double agreement_tolerance_m = 0.05;
  double min_agreement = 0.8;
  // After the first GICP pass, clouds agreeing on less than this share are
  // of different ground: the second pass is not run, and the verdict is
  // no overlap. (The second pass moved the agreement by at most 0.04 over
  // the tuning and evaluation pairs; registered pairs agreed on 0.82 or
  // more after the first.)
  double abandon_agreement = 0.65;
  double max_rms_m = 0.01;  // point-to-plane, over partners; above: doubtful
  // The source's residual against the target's surface above this many
  // times its residual against its own (at least sigma_floor_m): the
  // clouds are of different ground (no overlap). 0 turns it off.
  double max_residual_ratio = 2.0;
  // Standard deviation of the fit along its weakest direction (rotations as
  // the motion of a point at the clouds' radius), from the point-to-plane
  // normal equations over the partners and their residual.
  double sigma_floor_m = 0.004;       // the residual is taken as no less than this
  double degenerate_sigma_m = 0.006;  // above: degenerate along that direction
  double doubtful_sigma_m = 0.002;    // above: doubtful
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const RegistrationOptions& options);

enum class Verdict { kTrusted, kDoubtful, kDegenerate, kNoOverlap };
// "trusted", "doubtful", "degenerate", "no overlap".
const char* verdictName(Verdict verdict);

// What the result is worth, from the clouds alone (no truth).
struct RegistrationQuality {
  Verdict verdict = Verdict::kNoOverlap;
  std::string reason;    // why not trusted; empty when trusted
  double overlap = 0.0;  // share of the moved source points with a partner
  int partners = 0;
  double agreement = 0.0;  // share of the source's cells within 5 cm of the target's heights
  double rms_m = 0.0;      // point-to-plane over the partners
  // The source's points against its own surface, as rms_m against the
  // target's: what the noise alone leaves (0 with max_residual_ratio off).
  double self_rms_m = 0.0;
  // The fit's weakest direction and its standard deviation [m; rotations
  // at the clouds' radius], as a motion in the target's frame.
  double weakest_sigma_m = 0.0;
  Eigen::Vector3d weakest_translation = Eigen::Vector3d::Zero();  // its translation part
  Eigen::Vector3d weakest_rotation = Eigen::Vector3d::Zero();     // its rotation axis part
  std::string weakest_axis;  // "x", "y", "z", "roll", "pitch", "yaw", or mixed
  // Per axis of the target's frame [m, rad]: x, y, z, roll, pitch, yaw.
  Eigen::Matrix<double, 6, 1> sigma = Eigen::Matrix<double, 6, 1>::Zero();
};

struct Registration {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();  // source frame -> target frame
  bool converged = false;
  int iterations = 0;
  std::size_t pairs = 0;  // pairs weighed in the last iteration
  double rms_m = 0.0;     // point-to-plane over the partners (quality.rms_m)
  RegistrationQuality quality;
};

// Where each cloud's scanner stood, in that cloud's own frame (the origin
// of a scan in its sensor's frame); unknown, its points are used as they
// are.
struct ScannerOrigins {
  std::optional<Eigen::Vector3d> source, target;
};

// Aligns `source` to `target` from `initial` (e.g. dead reckoning). Throws
// std::invalid_argument for clouds too small to register or non-finite
// input.
Registration registerClouds(const Cloud& source, const Cloud& target,
                            const Eigen::Isometry3d& initial,
                            const RegistrationOptions& options = {},
                            const ScannerOrigins& scanners = {});

}  // namespace ambler::mapping
