#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "sampling/AutoSeeds.h"
#include "sampling/DeformableContour.h"
#include "sampling/Features.h"
#include "sampling/GraspPlan.h"
#include "sampling/SuperquadricFit.h"

namespace ambler::sampling {

// The sampling pipeline of the cmu-1990 paper's fig. 2, from a seed on:
// contour, the 3-D points it encloses, superquadric, grasp.
struct SamplingOptions {
  FeatureOptions features;
  ContourOptions contour;
  FitOptions fit;
  SeedOptions seeds;
  Gripper gripper;
  // The contour stops short of the rock's rim, where its lower flanks are:
  // the points within rim_px beyond it are taken too, except those less
  // than sand_clearance_m above the sand plane fitted around the rock.
  int rim_px = 2;
  double sand_clearance_m = 0.004;
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const SamplingOptions& options);

struct RockSample {
  Eigen::Vector2d seed{0, 0};  // x = column, y = row
  Contour contour;
  std::vector<Eigen::Vector3d> points;
  std::optional<Eigen::Hyperplane<double, 3>> sand;
  SuperquadricFit fit;
  double fit_ms = 0.0;
  GraspPlan grasp;
};

// The measured points where `mask` is set.
std::vector<Eigen::Vector3d> pointsInside(const sensor::StriperImage& image,
                                          const io::ByteImage& mask);

struct RockPoints {
  std::vector<Eigen::Vector3d> points;
  // The plane of the sand around the contour (normal up), when enough of
  // it was measured.
  std::optional<Eigen::Hyperplane<double, 3>> sand;
};

// The points of the rock a contour outlines: inside it, and on its rim
// above the sand (see SamplingOptions).
RockPoints rockPoints(const sensor::StriperImage& image, const Contour& contour,
                      const SamplingOptions& options = {});

// Throws std::invalid_argument for a bad seed or a contour around fewer than
// 11 measured points.
RockSample sampleRock(const sensor::StriperImage& image, const FeatureMap& features,
                      const Eigen::Vector2d& seed, const SamplingOptions& options = {},
                      const ContourObserver& observer = {});

}  // namespace ambler::sampling
