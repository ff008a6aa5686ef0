#pragma once

#include <Eigen/Core>
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
};

struct RockSample {
  Eigen::Vector2d seed{0, 0};  // x = column, y = row
  Contour contour;
  std::vector<Eigen::Vector3d> points;
  SuperquadricFit fit;
  double fit_ms = 0.0;
  GraspPlan grasp;
};

// The measured points where `mask` is set.
std::vector<Eigen::Vector3d> pointsInside(const sensor::StriperImage& image,
                                          const io::ByteImage& mask);

// Throws std::invalid_argument for a bad seed or a contour around fewer than
// 11 measured points.
RockSample sampleRock(const sensor::StriperImage& image, const FeatureMap& features,
                      const Eigen::Vector2d& seed, const SamplingOptions& options = {},
                      const ContourObserver& observer = {});

}  // namespace ambler::sampling
