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
  // `hint`, when not -1, is a point likely near the query (its nearest for a
  // query close by): its distance bounds the search from the start, which
  // then visits fewer branches; the answer is the same.
  Hit nearest(const Eigen::Vector3f& query, float max_distance2, int hint = -1) const;
  // Up to k nearest points, nearest first; returns how many were written.
  int nearest(const Eigen::Vector3f& query, int k, unsigned* indices, float* distance2) const;

 private:
  struct Tree;
  std::vector<Eigen::Vector3f> points_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace ambler::mapping
