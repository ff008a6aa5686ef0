#pragma once

#include <Eigen/Geometry>
#include <vector>

namespace ambler::mapping {

using Cloud = std::vector<Eigen::Vector3d>;

// bakambu-csa §2: ICP whose correspondences must agree in surface normal
// and in curvature change, not only be nearest (the paper's variant), on
// voxel-thinned clouds, point-to-plane steps. Pairs farther apart than
// three times the median are dropped each iteration: where two views do
// not overlap, points pair with the other cloud's edge and hold it back.
struct IcpOptions {
  double voxel_m = 0.07;             // thinning of both clouds (docs/mapping.md)
  double normal_radius_m = 0.45;     // neighbourhood of the normals and curvature
  double max_distance_m = 1.0;       // pairs farther apart are not matched
  double max_normal_angle_deg = 20;  // nor pairs whose normals differ more
  double max_curvature_change = 0.05;
  int max_iterations = 60;
  double min_step_m = 1e-4;  // a step moving no point more than this ends it
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const IcpOptions& options);

struct Registration {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();  // source frame -> target frame
  bool converged = false;
  int iterations = 0;
  std::size_t pairs = 0;  // correspondences kept in the last iteration
  double rms_m = 0.0;     // point-to-plane, over those pairs
};

// Aligns `source` to `target` from `initial` (e.g. dead reckoning). Throws
// std::invalid_argument for clouds too small to register or non-finite
// input.
Registration registerIcp(const Cloud& source, const Cloud& target, const Eigen::Isometry3d& initial,
                         const IcpOptions& options = {});

}  // namespace ambler::mapping
