#pragma once

#include <variant>
#include <vector>

#include "core/Superquadric.h"
#include "sim/Terrain.h"

namespace ambler::sim {

// One sinusoid of the rolling ground: amplitude * sin(kx x + ky y + phase).
struct Wave {
  double amplitude = 0.0;  // [m]
  double kx = 0.0;         // [rad/m]
  double ky = 0.0;
  double phase = 0.0;
};

// A rectangle in the x-y plane: centre, heading of its local x axis, half
// extents [m, rad].
struct Footprint {
  double cx = 0.0;
  double cy = 0.0;
  double yaw = 0.0;
  double half_x = 0.0;
  double half_y = 0.0;

  // Coordinates of (x, y) in the rectangle's frame.
  Eigen::Vector2d toLocal(double x, double y) const;
  bool contains(double x, double y) const;
  Box2 bounds() const;
};

// A block with a flat top `height` above the ground at its centre.
struct BoxObstacle {
  Footprint footprint;
  double height = 1.0;
};

// A pit with vertical walls and a flat floor `depth` below the ground at its
// centre.
struct Trench {
  Footprint footprint;
  double depth = 1.0;
};

// An incline rising along the local +x axis over the first `run` metres of
// the footprint, then a flat top, then a vertical drop at the far end.
struct Ramp {
  Footprint footprint;
  double run = 3.0;
  double height = 0.8;
};

// An upright superquadric rock; its centre may sit below the ground (buried).
struct Rock {
  Superquadric shape;
};

using Feature = std::variant<BoxObstacle, Trench, Ramp, Rock>;

// Everything that defines a procedural terrain: rolling ground plus
// features, within an extent.
struct TerrainDescription {
  Box2 extent{-20.0, -10.0, 20.0, 50.0};
  double base_height = 0.0;
  std::vector<Wave> waves;
  std::vector<Feature> features;
};

// Analytic terrain: z = rolling ground, carved by trenches, raised by boxes,
// ramps and rocks (the highest wins). Heights are exact, not sampled.
class ProceduralTerrain : public Terrain {
 public:
  explicit ProceduralTerrain(TerrainDescription description);

  double height(double x, double y) const override;
  double maxHeightIn(const Box2& box) const override;
  Box2 extent() const override { return description_.extent; }

  // The rolling ground alone, without features.
  double groundHeight(double x, double y) const;

  // Index into description().features of the feature that sets the height
  // at (x, y), or -1 where the rolling ground does.
  int featureAt(double x, double y) const;

  const TerrainDescription& description() const { return description_; }

 private:
  struct Evaluated {
    double z;
    int feature;
  };
  Evaluated evaluate(double x, double y) const;
  const std::vector<int>& featuresNear(double x, double y) const;

  TerrainDescription description_;
  double wave_slope_bound_ = 0.0;    // Lipschitz constant of the ground
  std::vector<double> feature_top_;  // absolute top height of each feature
  std::vector<Box2> feature_bounds_;
  // Uniform bins over the extent listing the features that overlap them.
  double bin_size_ = 2.0;
  int bin_cols_ = 0, bin_rows_ = 0;
  std::vector<std::vector<int>> bins_;
  std::vector<int> no_features_;
};

}  // namespace ambler::sim
