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
  double voxel_m = 0.15;             // thinning of both clouds
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

// Global localization without a prior on position or heading, of a scan
// into a coarse model (e.g. 1 m from orbital altimetry), given the scan's
// tilt from gravity (the rover's inclinometers): the levelled scan, binned
// into the model's cells at every heading step, is slid over the model's
// cells; the heading and shift whose heights differ least (up to one
// common offset) start ICP against the model. FPFH with RANSAC was tried
// first and failed on the 1 m model (docs/mapping.md).
struct GlobalOptions {
  double cell_m = 1.0;        // the model's resolution
  double yaw_step_deg = 2.0;  // headings tried
  double min_overlap = 0.6;   // of the scan's cells, over model cells
  int min_points_per_cell = 3;
  IcpOptions refine{.voxel_m = 0.2,
                    .normal_radius_m = 1.5,
                    .max_distance_m = 1.5,
                    .max_normal_angle_deg = 30,
                    .max_curvature_change = 0.1};
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const GlobalOptions& options);

// The rotation of sensor_to_world with its heading about the vertical
// taken out: what an inclinometer tells of the sensor's attitude.
Eigen::Matrix3d withoutYaw(const Eigen::Matrix3d& sensor_to_world);

// `tilt`: the scan frame's rotation to a level frame (withoutYaw). The
// result maps the scan into the model's frame; not converged, identity,
// when no placement overlaps the model enough. Throws
// std::invalid_argument for non-finite points or a scan too small.
Registration localize(const Cloud& scan, const Eigen::Matrix3d& tilt, const Cloud& model,
                      const GlobalOptions& options = {});

}  // namespace ambler::mapping
