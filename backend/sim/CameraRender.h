#pragma once

#include <Eigen/Core>

#include "io/Image.h"
#include "sim/ProceduralTerrain.h"
#include "sim/RayCaster.h"

namespace ambler::sim {

// A grey-level payload-camera image of the course (the input of ejiri §3,
// since no planetary images are packaged): a pinhole camera height_m above
// the ground at `ground_xy`, facing `heading` (0: +y), its axis alpha from
// the vertical, vertical field of view beta, square pixels. Lambertian
// ground under a low sun with cast shadows; sand bright with a fine grain,
// the course's features (rocks, boxes, trench walls, ramps) darker and
// coarser, as the paper assumes rough ground looks. Past the course's edge
// the ground goes on flat to the horizon; the sky is black.
struct CameraShot {
  int rows = 480, cols = 640;
  double alpha_deg = 78.0, beta_deg = 40.0, height_m = 1.5;
  Eigen::Vector2d ground_xy = Eigen::Vector2d::Zero();
  double heading = 0.0;             // [rad]
  double sun_elevation_deg = 35.0;  // above the horizon
  double sun_azimuth_deg = 60.0;    // from the camera's heading, to the left
  std::uint64_t texture_seed = 1;
};

struct RenderedImage {
  io::FloatImage grey;  // 0-255
  // Per pixel: 1 where the ray meets a feature standing more than
  // `rough_height_m` off the rolling ground (what should look dangerous),
  // 0 on the ground, 255 sky.
  io::ByteImage rough;
};

RenderedImage renderCamera(const ProceduralTerrain& terrain, const RayCaster& caster,
                           const CameraShot& shot, double rough_height_m = 0.15);

}  // namespace ambler::sim
