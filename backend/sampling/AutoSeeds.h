#pragma once

#include <Eigen/Core>
#include <vector>

#include "sampling/Features.h"
#include "sensor/StriperImage.h"

namespace ambler::sampling {

// cmu-1990 sampling paper §5: an object casts a range shadow on the side
// away from the projector, so a point inside it lies from the shadow's
// near edge towards the projector. In the image that direction points at
// the projector's projection (the epipole); the seed is taken a nominal
// object radius beyond the edge. Shadows too narrow (noise) or too wide (an
// object the gripper cannot take) are skipped, as are those touching the
// image border (the tray's edge, not an object).
struct SeedOptions {
  double radius_px = 8.0;     // nominal object radius in the image
  double min_width_px = 3.0;  // of the shadow across the light
  double max_width_px = 60.0;
  int min_shadow_px = 6;
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const SeedOptions& options);

struct Seed {
  Eigen::Vector2d pixel{0, 0};  // x = column, y = row
  int shadow_region = -1;       // the connected shadow it came from
  double shadow_width_px = 0;
};

std::vector<Seed> automaticSeeds(const sensor::StriperImage& image, const FeatureMap& features,
                                 const SeedOptions& options = {});

// Image scale at a world point: pixels per metre across the view.
double pixelsPerMetre(const sensor::PinholeCamera& camera, const Eigen::Vector3d& at);

}  // namespace ambler::sampling
