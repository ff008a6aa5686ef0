#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace ambler::mapping {

// A k-d tree over a fixed set of points (nanoflann), for nearest-neighbour
// queries from any thread at once.
class PointIndex {
 public:
  explicit PointIndex(std::vector<Eigen::Vector3f> points);
  ~PointIndex();
  PointIndex(const PointIndex&) = delete;
  PointIndex& operator=(const PointIndex&) = delete;

  const std::vector<Eigen::Vector3f>& points() const { return points_; }
  std::size_t size() const { return points_.size(); }

  struct Hit {
    int index = -1;
    float distance2 = 0.0f;  // squared [m^2]
  };
  // The nearest point, or index -1 when none lies within sqrt(max_distance2).
  Hit nearest(const Eigen::Vector3f& query, float max_distance2) const;
  // The nearest point, and its lead [m]: how much farther the next point
  // within sqrt(max_distance2) lies, or that distance itself when none
  // does. A query moved by less than half the lead has the same nearest
  // point.
  Hit nearestWithLead(const Eigen::Vector3f& query, float max_distance2, float& lead) const;
  // Up to k nearest points, nearest first; returns how many were written.
  int nearest(const Eigen::Vector3f& query, int k, unsigned* indices, float* distance2) const;

 private:
  struct Tree;
  std::vector<Eigen::Vector3f> points_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace ambler::mapping
