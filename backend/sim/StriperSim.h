#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "io/Image.h"
#include "sensor/StriperImage.h"
#include "sim/ProceduralTerrain.h"
#include "sim/RayCaster.h"

namespace ambler::sim {

// The light-striper of the sampling testbed: a camera looking down at the
// work area and a projector beside it (assumed geometry; the cmu-1990 paper
// gives only the 256x256 image size).
struct StriperModel {
  int rows = 256;
  int cols = 256;
  double horizontal_fov = 50.0 * M_PI / 180.0;  // [rad]
  Eigen::Vector3d camera_position{0.0, -0.6, 1.1};
  Eigen::Vector3d look_at{0.0, 0.0, 0.0};
  Eigen::Vector3d projector_position{0.5, -0.5, 0.8};
  double noise_sigma = 0.0005;  // along the camera ray [m]

  sensor::PinholeCamera camera() const;
};

// Label image of a simulated striper scene: what each camera ray hit.
inline constexpr unsigned char kLabelGround = 0;     // sand
inline constexpr unsigned char kLabelNothing = 255;  // missed the work area
// Any other value v: rock v - 1, i.e. TerrainDescription::features[v - 1].

struct StriperScene {
  sensor::StriperImage image;
  io::ByteImage labels;
};

// Ray-casts the camera; a surface point the projector cannot see (or that
// the camera misses) has no measurement, as in a real striper's range
// shadows. Intensity is Lambertian under the projector's light. Rocks are
// rendered as whole superquadrics (a heightfield would turn the part below
// a rock's widest outline into a vertical wall); the rest of the terrain,
// ground, boxes, trenches and ramps, through a ray caster.
class StriperRenderer {
 public:
  StriperRenderer(const ProceduralTerrain& terrain, RayCasterOptions options);
  StriperScene render(const StriperModel& model, std::uint64_t noise_seed) const;

 private:
  struct Hit {
    double t;
    int feature;  // index into the terrain's features, -1 for the ground
  };
  std::optional<Hit> firstHit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                              double max_range) const;
  Eigen::Vector3d normalAt(const Eigen::Vector3d& p, int feature) const;

  std::vector<int> ground_features_;                 // ground_'s feature index -> the terrain's
  ProceduralTerrain ground_;                         // the terrain without its rocks
  std::vector<std::pair<int, Superquadric>> rocks_;  // the terrain's feature index, shape
  RayCaster caster_;
};

// One image of a small scene (the sampling tray).
StriperScene simulateStriper(const ProceduralTerrain& terrain, const StriperModel& model,
                             std::uint64_t noise_seed);

}  // namespace ambler::sim
