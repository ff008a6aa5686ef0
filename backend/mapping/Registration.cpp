// Every PCL template the project instantiates for registration lives in
// this file (compile cost: ../shared/STACK.md).
#include "mapping/Registration.h"

#include <pcl/features/normal_3d.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/transformation_estimation_point_to_plane_lls.h>
#include <pcl/search/kdtree.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ambler::mapping {

void validate(const IcpOptions& o) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("icp option " + what);
  };
  require(o.voxel_m > 0 && o.voxel_m <= 1e4, "voxel_m must be in (0, 10 km]");
  require(o.normal_radius_m > 0 && o.normal_radius_m <= 1e5,
          "normal_radius_m must be in (0, 100 km]");
  require(o.max_distance_m > 0, "max_distance_m must be positive");
  require(o.max_normal_angle_deg > 0 && o.max_normal_angle_deg <= 180,
          "max_normal_angle_deg must be in (0, 180]");
  require(o.max_curvature_change > 0, "max_curvature_change must be positive");
  require(o.max_iterations >= 1 && o.max_iterations <= 10000,
          "max_iterations must be in [1, 10000]");
  require(o.min_step_m >= 0, "min_step_m must be >= 0");
}

namespace {

using Points = pcl::PointCloud<pcl::PointXYZ>;
using Oriented = pcl::PointCloud<pcl::PointNormal>;

Points::Ptr thinned(const Cloud& cloud, double voxel) {
  Points::Ptr raw(new Points), out(new Points);
  for (const auto& p : cloud) {
    if (!p.allFinite()) throw std::invalid_argument("registration: a point is not finite");
    raw->push_back({float(p.x()), float(p.y()), float(p.z())});
  }
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(raw);
  grid.setLeafSize(float(voxel), float(voxel), float(voxel));
  grid.filter(*out);
  return out;
}

// Points with unit normals (turned to face up: terrain seen from above)
// and curvature; points without enough neighbours are dropped.
Oriented::Ptr oriented(const Points::Ptr& points, double radius) {
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimate;
  pcl::PointCloud<pcl::Normal> normals;
  estimate.setInputCloud(points);
  estimate.setSearchMethod(
      pcl::search::KdTree<pcl::PointXYZ>::Ptr(new pcl::search::KdTree<pcl::PointXYZ>));
  estimate.setRadiusSearch(radius);
  estimate.compute(normals);
  Oriented::Ptr out(new Oriented);
  for (std::size_t i = 0; i < points->size(); ++i) {
    const auto& n = normals[i];
    if (!std::isfinite(n.normal_x) || !std::isfinite(n.curvature)) continue;
    pcl::PointNormal p;
    p.getVector3fMap() = (*points)[i].getVector3fMap();
    const float up = n.normal_z < 0 ? -1.0f : 1.0f;
    p.normal_x = up * n.normal_x, p.normal_y = up * n.normal_y, p.normal_z = up * n.normal_z;
    p.curvature = n.curvature;
    out->push_back(p);
  }
  return out;
}

Oriented::Ptr prepare(const Cloud& cloud, double voxel, double radius, const char* which) {
  auto out = oriented(thinned(cloud, voxel), radius);
  if (out->size() < 10)
    throw std::invalid_argument(std::string("registration: the ") + which + " has " +
                                std::to_string(out->size()) +
                                " points with normals after thinning; at least 10 needed");
  return out;
}

Eigen::Isometry3d toIsometry(const Eigen::Matrix4f& m) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.matrix() = m.cast<double>();
  return t;
}

Registration icp(const Oriented::Ptr& source, const Oriented::Ptr& target,
                 const Eigen::Isometry3d& initial, const IcpOptions& o) {
  pcl::KdTreeFLANN<pcl::PointNormal> tree;
  tree.setInputCloud(target);
  const float cos_limit = float(std::cos(o.max_normal_angle_deg * M_PI / 180));
  pcl::registration::TransformationEstimationPointToPlaneLLS<pcl::PointNormal, pcl::PointNormal>
      estimate;
  Registration r;
  r.transform = initial;
  Oriented moved;
  std::vector<int> index(1);
  std::vector<float> distance(1);
  double last_rms = INFINITY;
  int stalled = 0;
  for (r.iterations = 1; r.iterations <= o.max_iterations; ++r.iterations) {
    pcl::transformPointCloudWithNormals(*source, moved, r.transform.matrix().cast<float>());
    pcl::Correspondences candidates;
    std::vector<float> gaps;
    for (int i = 0; i < int(moved.size()); ++i) {
      if (tree.nearestKSearch(moved[std::size_t(i)], 1, index, distance) != 1) continue;
      if (distance[0] > o.max_distance_m * o.max_distance_m) continue;
      const auto& s = moved[std::size_t(i)];
      const auto& t = (*target)[std::size_t(index[0])];
      if (s.getNormalVector3fMap().dot(t.getNormalVector3fMap()) < cos_limit) continue;
      if (std::abs(s.curvature - t.curvature) > o.max_curvature_change) continue;
      candidates.emplace_back(i, index[0], distance[0]);
      gaps.push_back(distance[0]);
    }
    if (candidates.size() < 6) return r;
    // Pairs beyond three times the median gap go: where the views do not
    // overlap, points pair with the other cloud's edge and drag it along.
    std::nth_element(gaps.begin(), gaps.begin() + std::ptrdiff_t(gaps.size() / 2), gaps.end());
    const float limit = std::max(9.0f * gaps[gaps.size() / 2], float(o.voxel_m * o.voxel_m));
    pcl::Correspondences pairs;
    double sum = 0;
    for (const auto& c : candidates) {
      if (c.distance > limit) continue;
      pairs.push_back(c);
      const auto& s = moved[std::size_t(c.index_query)];
      const auto& t = (*target)[std::size_t(c.index_match)];
      const double d = (s.getVector3fMap() - t.getVector3fMap()).dot(t.getNormalVector3fMap());
      sum += d * d;
    }
    r.pairs = pairs.size();
    r.rms_m = pairs.empty() ? INFINITY : std::sqrt(sum / double(pairs.size()));
    if (pairs.size() < 6) return r;
    Eigen::Matrix4f step;
    estimate.estimateRigidTransformation(moved, *target, pairs, step);
    r.transform = toIsometry(step) * r.transform;
    // The largest move the step gave a point of the source.
    double largest = 0;
    for (const auto& p : moved)
      largest = std::max(largest, double((step.topLeftCorner<3, 3>() * p.getVector3fMap() +
                                          step.topRightCorner<3, 1>() - p.getVector3fMap())
                                             .norm()));
    // Converged when the step is negligible, or when the fit has stopped
    // improving (the pairs then flip between two sets of equal merit).
    stalled = std::abs(r.rms_m - last_rms) < 1e-6 ? stalled + 1 : 0;
    last_rms = r.rms_m;
    if (largest <= o.min_step_m || stalled >= 3) {
      r.converged = true;
      return r;
    }
  }
  r.iterations = o.max_iterations;
  return r;
}

}  // namespace

Registration registerIcp(const Cloud& source, const Cloud& target, const Eigen::Isometry3d& initial,
                         const IcpOptions& o) {
  validate(o);
  if (!initial.matrix().allFinite())
    throw std::invalid_argument("registration: the initial transform is not finite");
  return icp(prepare(source, o.voxel_m, o.normal_radius_m, "source"),
             prepare(target, o.voxel_m, o.normal_radius_m, "target"), initial, o);
}

}  // namespace ambler::mapping
