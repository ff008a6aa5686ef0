#include "mapping/TerrainPath.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <stdexcept>

namespace ambler::mapping {

void validate(const PathOptions& o) {
  if (!(o.max_slope_deg > 0 && o.max_slope_deg < 90))
    throw std::invalid_argument("path option max_slope_deg must be in (0, 90) degrees");
  if (!(o.slope_weight >= 0 && o.slope_weight <= 100))
    throw std::invalid_argument("path option slope_weight must be in [0, 100]");
  if (!(o.low_ground_weight >= 0 && o.low_ground_weight <= 100))
    throw std::invalid_argument("path option low_ground_weight must be in [0, 100]");
  if (!(o.simplification_slack >= 0 && o.simplification_slack <= 1))
    throw std::invalid_argument("path option simplification_slack must be in [0, 1]");
}

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Cost per metre over each triangle; infinite on impassable ones.
class TriangleCosts {
 public:
  TriangleCosts(const TerrainMesh& mesh, const PathOptions& o) : o_(o) {
    double z_lo = kInfinity, z_hi = -kInfinity;
    for (int t = 0; t < int(mesh.size()); ++t) {
      z_lo = std::min(z_lo, mesh.centre(t).z());
      z_hi = std::max(z_hi, mesh.centre(t).z());
    }
    const double limit = o.max_slope_deg * M_PI / 180;
    for (int t = 0; t < int(mesh.size()); ++t) {
      const double slope = mesh.slopeRad(t);
      double per_metre = 1.0;
      if (o.cost != PathCost::kDistance) per_metre += o.slope_weight * slope / limit;
      if (o.cost == PathCost::kHighGround && z_hi > z_lo)
        per_metre += o.low_ground_weight * (z_hi - mesh.centre(t).z()) / (z_hi - z_lo);
      per_metre_.push_back(slope > limit ? kInfinity : per_metre);
    }
    limit_rad_ = limit;
  }

  double perMetre(int t) const { return per_metre_[std::size_t(t)]; }
  bool passable(int t) const { return std::isfinite(perMetre(t)); }

  // From centre a to centre b: half the way over each, and the edge's own
  // slope counted like a triangle's.
  double edge(const TerrainMesh& mesh, int a, int b) const {
    const Eigen::Vector3d ca = mesh.centre(a), cb = mesh.centre(b);
    const double length = (cb - ca).norm();
    double cost = 0.5 * length * (perMetre(a) + perMetre(b));
    if (o_.cost != PathCost::kDistance) {
      const double run = (cb - ca).head<2>().norm();
      const double rise = run > 0 ? std::abs(cb.z() - ca.z()) / run : 0.0;
      cost += length * o_.slope_weight * std::atan(rise) / limit_rad_;
    }
    return cost;
  }

 private:
  const PathOptions& o_;
  std::vector<double> per_metre_;
  double limit_rad_ = 1.0;  // the slope limit
};

std::vector<int> dijkstra(const TerrainMesh& mesh, const TriangleCosts& costs, int start,
                          int goal) {
  std::vector<double> best(mesh.size(), kInfinity);
  std::vector<int> previous(mesh.size(), -1);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  best[std::size_t(start)] = 0;
  open.push({0, start});
  while (!open.empty()) {
    const auto [cost, t] = open.top();
    open.pop();
    if (cost > best[std::size_t(t)]) continue;
    if (t == goal) break;
    for (int n : mesh.neighbours[std::size_t(t)]) {
      if (n < 0 || !costs.passable(n)) continue;
      const double c = cost + costs.edge(mesh, t, n);
      if (c < best[std::size_t(n)]) {
        best[std::size_t(n)] = c;
        previous[std::size_t(n)] = t;
        open.push({c, n});
      }
    }
  }
  std::vector<int> path;
  if (!std::isfinite(best[std::size_t(goal)])) return path;
  for (int t = goal; t >= 0; t = previous[std::size_t(t)]) path.push_back(t);
  std::reverse(path.begin(), path.end());
  return path;
}

double segmentCost(const TerrainMesh& mesh, const TriangleLocator& locator,
                   const TriangleCosts& costs, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                   double step) {
  const double run = (b - a).head<2>().norm();
  const int n = std::max(1, int(std::ceil(run / step)));
  double cost = 0;
  Eigen::Vector3d previous = a;
  for (int i = 1; i <= n; ++i) {
    // Each piece is charged to the triangle under its middle.
    const Eigen::Vector2d mid = a.head<2>() + (b - a).head<2>() * ((i - 0.5) / n);
    const auto t = locator.at(mid);
    if (!t || !costs.passable(*t)) return kInfinity;
    const Eigen::Vector3d next =
        i == n ? b : mesh.pointOn(*t, a.head<2>() + (b - a).head<2>() * (double(i) / n));
    cost += (next - previous).norm() * costs.perMetre(*t);
    previous = next;
  }
  return cost;
}

// Sampling step along segments: a fraction of the smallest triangles' size.
double samplingStep(const TerrainMesh& mesh) {
  double smallest = kInfinity;
  for (int t = 0; t < int(mesh.size()); ++t) smallest = std::min(smallest, mesh.areaXY(t));
  return std::max(1e-3, 0.25 * std::sqrt(2 * smallest));
}

}  // namespace

double polylineCost(const TerrainMesh& mesh, const TriangleLocator& locator,
                    const std::vector<Eigen::Vector3d>& polyline, const PathOptions& options) {
  validate(options);
  const TriangleCosts costs(mesh, options);
  const double step = samplingStep(mesh);
  double cost = 0;
  for (std::size_t i = 1; i < polyline.size(); ++i)
    cost += segmentCost(mesh, locator, costs, polyline[i - 1], polyline[i], step);
  return cost;
}

TerrainPath planPath(const TerrainMesh& mesh, const Eigen::Vector2d& from,
                     const Eigen::Vector2d& to, const PathOptions& o) {
  validate(o);
  TerrainPath path;
  const TriangleLocator locator(mesh);
  const auto start = locator.at(from), goal = locator.at(to);
  if (!start || !goal) {
    path.reason = std::string(!start ? "the start" : "the goal") + " is not on the mesh";
    return path;
  }
  const TriangleCosts costs(mesh, o);
  if (!costs.passable(*start) || !costs.passable(*goal)) {
    path.reason = std::string(!costs.passable(*start) ? "the start" : "the goal") +
                  " is on a triangle steeper than the slope limit";
    return path;
  }
  path.triangles = dijkstra(mesh, costs, *start, *goal);
  if (path.triangles.empty()) {
    path.reason = "no way over passable triangles joins the start to the goal";
    return path;
  }
  path.raw.push_back(mesh.pointOn(*start, from));
  for (std::size_t i = 1; i + 1 < path.triangles.size(); ++i)
    path.raw.push_back(mesh.centre(path.triangles[i]));
  path.raw.push_back(mesh.pointOn(*goal, to));
  const double step = samplingStep(mesh);
  std::vector<double> piece(path.raw.size(), 0.0);  // raw cost up to each waypoint
  for (std::size_t i = 1; i < path.raw.size(); ++i)
    piece[i] = piece[i - 1] + segmentCost(mesh, locator, costs, path.raw[i - 1], path.raw[i], step);
  path.raw_cost = piece.back();
  // Greedy: from each kept waypoint, the farthest one reachable in a
  // straight line within the slack.
  std::size_t i = 0;
  path.simplified.push_back(path.raw[0]);
  while (i + 1 < path.raw.size()) {
    std::size_t next = i + 1;
    double next_cost = piece[i + 1] - piece[i];
    for (std::size_t j = path.raw.size() - 1; j > i + 1; --j) {
      const double c = segmentCost(mesh, locator, costs, path.raw[i], path.raw[j], step);
      if (c <= (1 + o.simplification_slack) * (piece[j] - piece[i])) {
        next = j, next_cost = c;
        break;
      }
    }
    path.simplified.push_back(path.raw[next]);
    path.simplified_cost += next_cost;
    i = next;
  }
  for (std::size_t k = 1; k < path.simplified.size(); ++k)
    path.length_m += (path.simplified[k] - path.simplified[k - 1]).norm();
  path.found = true;
  return path;
}

}  // namespace ambler::mapping
