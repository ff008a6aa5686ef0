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
#include <climits>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

namespace ambler::mapping {

void validate(const IcpOptions& o) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("icp option " + what);
  };
  require(o.voxel_m > 0 && o.voxel_m <= 10, "voxel_m must be in (0, 10] m");
  require(o.normal_radius_m > 0 && o.normal_radius_m <= 50, "normal_radius_m must be in (0, 50] m");
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

namespace {

// Mean height per cell of a grid over the x-y plane, for cells with at
// least `min_points` points.
struct Cell {
  int x, y;
  double z;
};

std::vector<Cell> heightCells(const std::vector<Eigen::Vector3d>& points, double cell,
                              int min_points) {
  std::map<std::pair<int, int>, std::pair<double, int>> sums;
  for (const auto& p : points) {
    auto& s = sums[{int(std::floor(p.x() / cell)), int(std::floor(p.y() / cell))}];
    s.first += p.z(), ++s.second;
  }
  std::vector<Cell> out;
  for (const auto& [key, s] : sums)
    if (s.second >= min_points) out.push_back({key.first, key.second, s.first / s.second});
  return out;
}

// The model's cells as a dense raster (NaN where it has none).
struct HeightRaster {
  int x0 = 0, y0 = 0, cols = 0, rows = 0;
  std::vector<double> z;

  explicit HeightRaster(const std::vector<Cell>& cells) {
    int x1 = INT_MIN, y1 = INT_MIN;
    x0 = y0 = INT_MAX;
    for (const auto& c : cells)
      x0 = std::min(x0, c.x), y0 = std::min(y0, c.y), x1 = std::max(x1, c.x),
      y1 = std::max(y1, c.y);
    cols = cells.empty() ? 0 : x1 - x0 + 1;
    rows = cells.empty() ? 0 : y1 - y0 + 1;
    z.assign(std::size_t(cols) * std::size_t(rows), NAN);
    for (const auto& c : cells)
      z[std::size_t(c.y - y0) * std::size_t(cols) + std::size_t(c.x - x0)] = c.z;
  }
  double at(int x, int y) const {
    if (x < x0 || y < y0 || x >= x0 + cols || y >= y0 + rows) return NAN;
    return z[std::size_t(y - y0) * std::size_t(cols) + std::size_t(x - x0)];
  }
};

struct Candidate {
  double score = INFINITY;  // height misfit over the scan's relief
  double yaw = 0.0, dz = 0.0;
  int dx = 0, dy = 0;
};

// The best shift of `scan` (cells relative to the sensor) over `model`.
void matchShifts(const std::vector<Cell>& scan, const HeightRaster& model, double yaw,
                 double min_overlap, Candidate& best) {
  const auto needed = std::max<std::size_t>(std::size_t(min_overlap * double(scan.size())), 10);
  for (int dy = model.y0; dy < model.y0 + model.rows; ++dy)
    for (int dx = model.x0; dx < model.x0 + model.cols; ++dx) {
      double sum = 0, sum2 = 0, scan_sum = 0, scan_sum2 = 0;
      std::size_t n = 0;
      for (const auto& c : scan) {
        const double m = model.at(c.x + dx, c.y + dy);
        if (std::isnan(m)) continue;
        const double d = m - c.z;
        sum += d, sum2 += d * d, scan_sum += c.z, scan_sum2 += c.z * c.z, ++n;
      }
      if (n < needed) continue;
      // The height differences' variance against the scan's own over the
      // overlap: flat ground fits a flat scan anywhere, so a placement
      // counts by how much of the scan's relief it explains.
      const double mean = sum / double(n);
      const double misfit = sum2 / double(n) - mean * mean;
      const double relief = scan_sum2 / double(n) - std::pow(scan_sum / double(n), 2);
      const double score = misfit / std::max(relief, 1e-6);
      if (score < best.score) best = {score, yaw, mean, dx, dy};
    }
}

}  // namespace

Eigen::Matrix3d withoutYaw(const Eigen::Matrix3d& sensor_to_world) {
  const double yaw = std::atan2(sensor_to_world(1, 0), sensor_to_world(0, 0));
  return Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * sensor_to_world;
}

void validate(const GlobalOptions& o) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("localization option " + what);
  };
  require(o.cell_m > 0 && o.cell_m <= 100, "cell_m must be in (0, 100] m");
  require(o.yaw_step_deg > 0 && o.yaw_step_deg <= 45, "yaw_step_deg must be in (0, 45]");
  require(o.min_overlap > 0 && o.min_overlap <= 1, "min_overlap must be in (0, 1]");
  require(o.min_points_per_cell >= 1, "min_points_per_cell must be >= 1");
  validate(o.refine);
}

Registration localize(const Cloud& scan, const Eigen::Matrix3d& tilt, const Cloud& model,
                      const GlobalOptions& o) {
  validate(o);
  for (const auto* cloud : {&scan, &model})
    for (const auto& p : *cloud)
      if (!p.allFinite()) throw std::invalid_argument("localization: a point is not finite");
  const HeightRaster model_grid(heightCells(model, o.cell_m, 1));
  Cloud levelled;
  for (const auto& p : scan) levelled.push_back(tilt * p);
  Candidate best;
  for (double yaw = 0; yaw < 2 * M_PI; yaw += o.yaw_step_deg * M_PI / 180) {
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    Cloud turned;
    for (const auto& p : levelled) turned.push_back(turn * p);
    const auto scan_grid = heightCells(turned, o.cell_m, o.min_points_per_cell);
    if (scan_grid.size() < 10)
      throw std::invalid_argument("localization: the scan covers " +
                                  std::to_string(scan_grid.size()) + " cells; at least 10 needed");
    matchShifts(scan_grid, model_grid, yaw, o.min_overlap, best);
  }
  if (!std::isfinite(best.score)) return {};
  Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
  start.translation() = Eigen::Vector3d(best.dx * o.cell_m, best.dy * o.cell_m, best.dz);
  start.linear() = Eigen::AngleAxisd(best.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * tilt;
  return registerIcp(scan, model, start, o.refine);
}

}  // namespace ambler::mapping
