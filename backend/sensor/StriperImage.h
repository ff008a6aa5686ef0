#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <string>
#include <vector>

namespace ambler::sensor {

// Pinhole model of the light-striper's camera. Camera frame: x right, y down
// the image, z along the optical axis; pixel (r, c) looks along
// ((c - cx) / fx, (r - cy) / fy, 1).
struct PinholeCamera {
  int rows = 0;
  int cols = 0;
  double fx = 0.0;
  double fy = 0.0;
  double cx = 0.0;
  double cy = 0.0;
  Eigen::Isometry3d camera_to_world = Eigen::Isometry3d::Identity();

  Eigen::Vector3d rayInWorld(double r, double c) const {
    const Eigen::Vector3d d((c - cx) / fx, (r - cy) / fy, 1.0);
    return camera_to_world.linear() * d.normalized();
  }
  Eigen::Vector3d center() const { return camera_to_world.translation(); }
  // Where `world` appears in the image: (column, row). A point on the
  // camera's focal plane is taken 1 nm in front of it.
  Eigen::Vector2d pixelOf(const Eigen::Vector3d& world) const {
    const Eigen::Vector3d p = camera_to_world.inverse() * world;
    const double z = std::abs(p.z()) > 1e-9 ? p.z() : 1e-9;
    return {fx * p.x() / z + cx, fy * p.y() / z + cy};
  }
  bool inFront(const Eigen::Vector3d& world) const {
    return (camera_to_world.inverse() * world).z() > 0;
  }
};

// One light-striper acquisition as in the cmu-1990 sampling paper: four
// images of the same size, X, Y, Z [m] in a fixed reference frame and an
// intensity image [0..1]. Pixels without a measurement (range shadows: lit
// by the projector but hidden from the camera, or the reverse) hold NaN in
// X, Y and Z.
struct StriperImage {
  PinholeCamera camera;
  Eigen::Vector3d projector_position = Eigen::Vector3d::Zero();
  std::vector<float> x, y, z, intensity;

  int rows() const { return camera.rows; }
  int cols() const { return camera.cols; }
  std::size_t index(int r, int c) const { return std::size_t(r) * camera.cols + c; }
  bool hasPoint(int r, int c) const { return std::isfinite(x[index(r, c)]); }
  Eigen::Vector3d point(int r, int c) const {
    const auto i = index(r, c);
    return {x[i], y[i], z[i]};
  }
  int pointCount() const;
};

// Describes the first inconsistency (sizes, intrinsics, pose, partial NaN
// triples), or returns an empty string when the image is usable.
std::string findProblem(const StriperImage& image);

}  // namespace ambler::sensor
