#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <string>
#include <vector>

#include "sensor/SphericalPolar.h"

namespace ambler::sensor {

// krotkov1989 §3.3: range error is normal with sigma = k * rho^2 [m].
inline double rangeSigma(double rho, double k) { return k * rho * rho; }

// One scan of the laser rangefinder: ranges in metres on the scan geometry,
// 0 or NaN where there was no return, optional reflectance of the same size.
struct RangeImage {
  ScanGeometry geometry;
  Eigen::Isometry3d sensor_to_world = Eigen::Isometry3d::Identity();
  double range_sigma_k = 0.0;      // [1/m]
  std::vector<float> range;        // rows * cols, row-major [m]
  std::vector<float> reflectance;  // empty, or rows * cols

  int rows() const { return geometry.rows; }
  int cols() const { return geometry.cols; }
  float at(int r, int c) const { return range[std::size_t(r) * geometry.cols + c]; }
  bool hasReturn(int r, int c) const {
    const float v = at(r, c);
    return std::isfinite(v) && v > 0.0f;
  }
  Eigen::Vector3d pointInSensor(int r, int c) const {
    return toCartesian({at(r, c), geometry.phi(r), geometry.theta(c)});
  }
  Eigen::Vector3d pointInWorld(int r, int c) const { return sensor_to_world * pointInSensor(r, c); }
  int returnCount() const;
  // Every return as a point (eq. 1), row by row, in the sensor's frame or
  // in the world's.
  std::vector<Eigen::Vector3d> pointsInSensor() const;
  std::vector<Eigen::Vector3d> pointsInWorld() const;
};

// Describes the first inconsistency of a range image (sizes, steps, noise
// constant, pose not rigid), or returns an empty string when it is usable.
std::string findProblem(const RangeImage& image);

}  // namespace ambler::sensor
