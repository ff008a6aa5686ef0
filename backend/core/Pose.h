#pragma once

#include <Eigen/Geometry>
#include <vector>

namespace ambler {

// 4x4 poses as files store them: 16 numbers, row-major.
inline Eigen::Isometry3d poseFromRowMajor(const std::vector<double>& v) {
  Eigen::Isometry3d pose;
  for (int i = 0; i < 16; ++i) pose.matrix()(i / 4, i % 4) = v.at(std::size_t(i));
  return pose;
}

inline std::vector<double> toRowMajor(const Eigen::Isometry3d& pose) {
  std::vector<double> v(16);
  for (int i = 0; i < 16; ++i) v[std::size_t(i)] = pose.matrix()(i / 4, i % 4);
  return v;
}

// True when the rotation block is orthonormal with determinant +1 and the
// last row is (0 0 0 1), to `tolerance`.
inline bool isRigid(const Eigen::Matrix4d& pose, double tolerance = 1e-6) {
  if (!pose.allFinite()) return false;
  const Eigen::Matrix3d r = pose.topLeftCorner<3, 3>();
  const double orthonormality =
      (r * r.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  const double last_row = (pose.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff();
  return orthonormality < tolerance && last_row < tolerance &&
         std::abs(r.determinant() - 1.0) < tolerance;
}

}  // namespace ambler
