#pragma once

#include <Eigen/Core>
#include <vector>

namespace ambler::gait {

// A convex polygon on the ground plane, counter-clockwise, not closed.
using ConvexPolygon = std::vector<Eigen::Vector2d>;

// Counter-clockwise convex hull (Andrew's monotone chain); collinear
// points dropped.
ConvexPolygon convexHull(std::vector<Eigen::Vector2d> points);

// The support polygon of a stance: the hull of the supporting feet
// (cmu-1990 'Planning strategies', Gaits).
inline ConvexPolygon supportPolygon(const std::vector<Eigen::Vector2d>& feet) {
  return convexHull(feet);
}

// The conservative support polygon: the intersection of the support
// polygons with each supporting foot removed in turn, so a centre of
// gravity inside it stays supported if any one leg fails (cmu-1990, fig. 3
// and 'Planning strategies' figs. 4-5). Empty with fewer than four feet.
ConvexPolygon conservativeSupportPolygon(const std::vector<Eigen::Vector2d>& feet);

// Intersection of two convex polygons (clip of `subject` by each edge of
// `clip`).
ConvexPolygon intersect(const ConvexPolygon& subject, const ConvexPolygon& clip);

double area(const ConvexPolygon& polygon);

// Stability margin: distance from p to the polygon's boundary, positive
// inside, negative outside; -infinity for an empty or degenerate polygon.
double stabilityMargin(const ConvexPolygon& polygon, const Eigen::Vector2d& p);

// The stability margin of p in the conservative support polygon of `feet`
// without building it: the largest disk about p inside every one-leg-removed
// hull is the one inside their intersection, so for p inside the CSP this
// equals stabilityMargin(conservativeSupportPolygon(feet), p); outside it
// is negative (not necessarily the distance). Allocation-free, for the
// planner's inner loops. At most six feet.
double conservativeMargin(const std::vector<Eigen::Vector2d>& feet, const Eigen::Vector2d& p);

}  // namespace ambler::gait
