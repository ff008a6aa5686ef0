#include "gait/Support.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace ambler::gait {

namespace {

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

double segmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                       const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

}  // namespace

ConvexPolygon convexHull(std::vector<Eigen::Vector2d> points) {
  std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (points.size() < 3) return points;
  ConvexPolygon hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {  // lower chain
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, t = k + 1; i-- > 0;) {  // upper chain
    while (k >= t && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

ConvexPolygon intersect(const ConvexPolygon& subject, const ConvexPolygon& clip) {
  ConvexPolygon out = subject;
  for (std::size_t i = 0; i < clip.size() && !out.empty(); ++i) {
    const Eigen::Vector2d& a = clip[i];
    const Eigen::Vector2d& b = clip[(i + 1) % clip.size()];
    ConvexPolygon in;
    in.swap(out);
    for (std::size_t j = 0; j < in.size(); ++j) {
      const Eigen::Vector2d& p = in[j];
      const Eigen::Vector2d& q = in[(j + 1) % in.size()];
      const double dp = cross(a, b, p), dq = cross(a, b, q);
      if (dp >= 0) out.push_back(p);
      if ((dp >= 0) != (dq >= 0)) out.push_back(p + (q - p) * (dp / (dp - dq)));
    }
    // A vertex on the clip line comes out twice; near-duplicates would make
    // edges of no length whose direction is noise.
    ConvexPolygon kept;
    for (const auto& v : out)
      if (kept.empty() || (v - kept.back()).norm() > 1e-9) kept.push_back(v);
    while (kept.size() > 1 && (kept.front() - kept.back()).norm() <= 1e-9) kept.pop_back();
    out.swap(kept);
  }
  return out.size() < 3 ? ConvexPolygon{} : out;
}

ConvexPolygon conservativeSupportPolygon(const std::vector<Eigen::Vector2d>& feet) {
  if (feet.size() < 4) return {};
  ConvexPolygon csp;
  for (std::size_t skip = 0; skip < feet.size(); ++skip) {
    std::vector<Eigen::Vector2d> rest;
    for (std::size_t i = 0; i < feet.size(); ++i)
      if (i != skip) rest.push_back(feet[i]);
    const ConvexPolygon hull = convexHull(rest);
    csp = skip == 0 ? hull : intersect(csp, hull);
    if (csp.size() < 3) return {};
  }
  return csp;
}

double area(const ConvexPolygon& polygon) {
  double twice = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const auto& a = polygon[i];
    const auto& b = polygon[(i + 1) % polygon.size()];
    twice += a.x() * b.y() - a.y() * b.x();
  }
  return 0.5 * std::abs(twice);
}

double stabilityMargin(const ConvexPolygon& polygon, const Eigen::Vector2d& p) {
  if (polygon.size() < 3) return -std::numeric_limits<double>::infinity();
  bool inside = true;
  double distance = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const auto& a = polygon[i];
    const auto& b = polygon[(i + 1) % polygon.size()];
    const double length = (b - a).norm();
    if (length <= 1e-9) continue;
    if (cross(a, b, p) / length < -1e-9) inside = false;
    distance = std::min(distance, segmentDistance(p, a, b));
  }
  return inside ? distance : -distance;
}

double conservativeMargin(const std::vector<Eigen::Vector2d>& feet, const Eigen::Vector2d& p) {
  const std::size_t n = feet.size();
  if (n < 4 || n > 6)
    return n > 6 ? stabilityMargin(conservativeSupportPolygon(feet), p)
                 : -std::numeric_limits<double>::infinity();
  std::array<Eigen::Vector2d, 6> sorted;
  for (std::size_t i = 0; i < n; ++i) {  // insertion sort by x, then y
    std::size_t j = i;
    for (; j > 0 && (feet[i].x() < sorted[j - 1].x() ||
                     (feet[i].x() == sorted[j - 1].x() && feet[i].y() < sorted[j - 1].y()));
         --j)
      sorted[j] = sorted[j - 1];
    sorted[j] = feet[i];
  }
  double margin = std::numeric_limits<double>::infinity();
  std::array<Eigen::Vector2d, 12> hull;
  for (std::size_t skip = 0; skip < n; ++skip) {
    // Monotone chain over the sorted feet without `skip`.
    std::size_t k = 0;
    auto push = [&](std::size_t i, std::size_t floor) {
      while (k >= floor && cross(hull[k - 2], hull[k - 1], sorted[i]) <= 0) --k;
      hull[k++] = sorted[i];
    };
    for (std::size_t i = 0; i < n; ++i)
      if (i != skip) push(i, 2);
    const std::size_t lower = k + 1;
    for (std::size_t i = n; i-- > 0;)
      if (i != skip) push(i, lower);
    --k;  // the first point closes the chain
    if (k < 3) return -std::numeric_limits<double>::infinity();
    double inside = std::numeric_limits<double>::infinity(), outside = 0.0;
    for (std::size_t i = 0; i < k; ++i) {
      const Eigen::Vector2d& a = hull[i];
      const Eigen::Vector2d& b = hull[(i + 1) % k];
      const double length = (b - a).norm();
      if (length <= 1e-12) continue;
      const double d = cross(a, b, p) / length;  // signed distance to the edge's line
      if (d < 0) outside = std::max(outside, segmentDistance(p, a, b));
      inside = std::min(inside, d);
    }
    margin = std::min(margin, outside > 0 ? -outside : inside);
  }
  return margin;
}

}  // namespace ambler::gait
