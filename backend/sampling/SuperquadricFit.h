#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "core/Superquadric.h"

namespace ambler::sampling {

// cmu-1990 sampling paper §3.2, after Solina: Levenberg-Marquardt on the
// residuals sqrt(a1 a2 a3) (F^eps1 - 1) of the points (eq. 6 with Solina's
// two refinements: F^eps1 makes the error independent of the roundness, and
// the volume factor prefers the smallest superquadric that fits a partial
// view), from the ellipsoid of the points' moments. 11 parameters: sizes,
// roundness (eps1, eps2 in [0.1, 2]), position and orientation (updated on
// SO(3)). The robust variant re-weights each iteration with Cauchy weights
// scaled by the residuals' median absolute deviation, so that stray sand
// points and outliers lose their pull.
enum class FitResidual {
  kSolina,  // sqrt(a1 a2 a3) (F^eps1 - 1), the paper's choice
  kRadial,  // |x| (1 - F^(-eps1/2)): the radial distance to the surface
};

struct FitOptions {
  FitResidual residual = FitResidual::kRadial;  // measured better: docs/sampling.md
  bool robust = false;
  int max_iterations = 200;
  double tolerance = 1e-8;  // relative decrease of the cost that ends the fit
  // In robust standard deviations (1.4826 MAD). Tighter than the usual
  // 2.385: a fifth of stray points inflate the MAD (docs/sampling.md).
  double cauchy_scale = 1.5;
  // No size may exceed this multiple of the points' largest horizontal
  // half-extent: a view of a rock's top cannot support more, and without a
  // bound the fit of a cap can run off into a tall column.
  double max_size_ratio = 2.0;
  // With a ground plane, a weak prior that the rock rests on it: the
  // residual resting_weight sqrt(n) times the height of its lowest point
  // above the plane joins the n points'. A view from above leaves a rock's
  // underside unseen, and a boxy rock's vertical flanks fit a taller shape
  // sunk deeper just as well; the prior settles that choice and little else
  // (0 turns it off; measured in docs/sampling.md).
  double resting_weight = 0.01;
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const FitOptions& options);

struct SuperquadricFit {
  Superquadric shape;
  double rms_m = 0.0;         // radial distance to the surface, points of weight >= 0.5 [m]
  double inlier_share = 1.0;  // share of the points of weight >= 0.5
  int iterations = 0;
  bool converged = false;
};

// The starting point: centroid, principal axes (z the one nearest the
// vertical, x the longer of the others), sizes sqrt(3 lambda), eps = 1.
Superquadric momentEllipsoid(const std::vector<Eigen::Vector3d>& points);

// The points nearest (Mahalanobis) the mean of the nearest, `keep` of them,
// after a few rounds: a start that outliers do not drag.
std::vector<Eigen::Vector3d> trimmedCore(const std::vector<Eigen::Vector3d>& points, double keep);

// The largest relative error of `fit`'s sizes against `truth`'s, each true
// axis matched to the fitted axis nearest its direction.
double sizeError(const Superquadric& fit, const Superquadric& truth);

// Throws std::invalid_argument for fewer than 11 points or non-finite ones.
SuperquadricFit fitSuperquadric(const std::vector<Eigen::Vector3d>& points,
                                const FitOptions& options = {},
                                const std::optional<Eigen::Hyperplane<double, 3>>& ground = {});

}  // namespace ambler::sampling
