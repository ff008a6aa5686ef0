#include "mapping/PointIndex.h"

#include <array>
#include <cmath>
#include <nanoflann.hpp>

namespace ambler::mapping {

namespace {

struct Dataset {
  const std::vector<Eigen::Vector3f>* points;
  std::size_t kdtree_get_point_count() const { return points->size(); }
  float kdtree_get_pt(std::size_t i, std::size_t dim) const { return (*points)[i][int(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using KdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Dataset>, Dataset, 3>;

}  // namespace

struct PointIndex::Tree {
  Dataset dataset;
  KdTree tree;
  explicit Tree(const std::vector<Eigen::Vector3f>& points)
      : dataset{&points}, tree(3, dataset, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {}
};

PointIndex::PointIndex(std::vector<Eigen::Vector3f> points)
    : points_(std::move(points)), tree_(std::make_unique<Tree>(points_)) {}

PointIndex::~PointIndex() = default;

PointIndex::Hit PointIndex::nearest(const Eigen::Vector3f& query, float max_distance2) const {
  if (points_.empty()) return {};
  // The result set starts with the limit as its worst distance, so that the
  // tree prunes everything farther at once.
  unsigned index = 0;
  float d2 = 0;
  nanoflann::KNNResultSet<float, unsigned> result(1);
  result.init(&index, &d2);
  d2 = max_distance2;
  tree_->tree.findNeighbors(result, query.data(), nanoflann::SearchParams());
  if (result.size() != 1 || d2 > max_distance2) return {};
  return {int(index), d2};
}

PointIndex::Hit PointIndex::nearestWithLead(const Eigen::Vector3f& query, float max_distance2,
                                            float& lead) const {
  lead = 0.0f;
  if (points_.empty()) return {};
  std::array<unsigned, 2> index{};
  std::array<float, 2> d2{};
  nanoflann::KNNResultSet<float, unsigned> result(2);
  result.init(index.data(), d2.data());
  d2[1] = max_distance2;  // the bound, as in nearest()
  tree_->tree.findNeighbors(result, query.data(), nanoflann::SearchParams());
  if (result.size() == 0 || d2[0] > max_distance2) return {};
  lead = std::sqrt(d2[1]) - std::sqrt(d2[0]);  // d2[1] stays the bound when one point is found
  return {int(index[0]), d2[0]};
}

int PointIndex::nearest(const Eigen::Vector3f& query, int k, unsigned* indices,
                        float* distance2) const {
  if (points_.empty() || k <= 0) return 0;
  return int(tree_->tree.knnSearch(query.data(), std::size_t(k), indices, distance2));
}

}  // namespace ambler::mapping
