#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "mapping/TerrainMesh.h"

namespace ambler::mapping {

// bakambu-csa §4: what an edge of the triangle graph costs.
enum class PathCost {
  kDistance,   // the length travelled
  kSlope,      // length, more on steep triangles and steep edges
  kHighGround  // as kSlope, more on low ground (a better view of the terrain)
};

struct PathOptions {
  PathCost cost = PathCost::kSlope;
  double max_slope_deg = 20.0;     // triangles steeper than this are not entered
  double slope_weight = 2.0;       // cost per metre grows by this at the slope limit
  double low_ground_weight = 1.0;  // cost per metre grows by this at the lowest altitude
  // The simplified path may cost this much more than the raw one.
  double simplification_slack = 0.05;
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const PathOptions& options);

struct TerrainPath {
  bool found = false;
  std::string reason;                // why not, when not found
  std::vector<int> triangles;        // from the start's triangle to the goal's
  std::vector<Eigen::Vector3d> raw;  // start, triangle centres, goal
  std::vector<Eigen::Vector3d> simplified;
  double raw_cost = 0.0, simplified_cost = 0.0;  // [m, weighted]
  double length_m = 0.0;                         // of the simplified path, in 3-D
};

// Dijkstra over the graph of passable triangles (edges between neighbours,
// costed as the options say), waypoints at the triangle centres, then
// simplified: a waypoint goes when the straight line that skips it stays
// on passable triangles and costs at most the slack more.
TerrainPath planPath(const TerrainMesh& mesh, const Eigen::Vector2d& from,
                     const Eigen::Vector2d& to, const PathOptions& options = {});

// The cost of following a polyline over the mesh: its length over each
// triangle times that triangle's cost per metre; infinite where it leaves
// the mesh or crosses an impassable triangle.
double polylineCost(const TerrainMesh& mesh, const TriangleLocator& locator,
                    const std::vector<Eigen::Vector3d>& polyline, const PathOptions& options);

}  // namespace ambler::mapping
