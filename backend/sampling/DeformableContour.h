#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "io/Image.h"
#include "sampling/Features.h"

namespace ambler::sampling {

// cmu-1990 sampling paper §3.1: a closed contour in the image grows out
// from a seed inside an object until the forces on it balance: attraction
// to the nearest feature (searched along 16 directions around the normal),
// attraction back to the seed beyond half the largest expected radius, and
// an internal force that keeps it within K of its best-fit ellipse.
struct ContourOptions {
  double r_max_px = 40.0;   // largest expected object radius in the image
  double k_internal = 0.4;  // allowed distance from the ellipse, in its mean radii
  double spacing_px = 2.0;  // between contour points after resampling
  int max_iterations = 300;
  double free_growth = 0.25;  // feature force where no feature is within r_max
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const ContourOptions& options);

// Image coordinates: x = column, y = row (pixel centres at integers).
struct Contour {
  std::vector<Eigen::Vector2d> points;  // closed, counter-clockwise on screen
  int iterations = 0;
  bool converged = false;  // false: stopped by max_iterations
  double areaPx() const;
};

using ContourObserver = std::function<void(const Contour&)>;

// Grows from `seed` (x = column, y = row). A seed on a feature or outside the
// image throws std::invalid_argument. `observer` sees each iteration.
Contour growContour(const FeatureMap& features, const Eigen::Vector2d& seed,
                    const ContourOptions& options = {}, const ContourObserver& observer = {});

// 255 inside the contour, 0 outside. With `to_features`, also the pixel
// between the contour and the features it stopped one pixel short of: the
// object's outline. Without, the interior only: points for a fit, with no
// sand from the rim.
io::ByteImage contourMask(const Contour& contour, int rows, int cols, bool to_features = true);

}  // namespace ambler::sampling
