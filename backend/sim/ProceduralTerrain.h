#pragma once

#include <array>
#include <variant>
#include <vector>

#include "core/Superquadric.h"
#include "sim/Terrain.h"
#include "sim/WaveSum.h"

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

// A pit with a flat floor `depth` below the ground at its centre. Its long
// walls (along the local x axis) drop over a horizontal run of `wall_run`
// each: 0 gives vertical walls, half_y a V-shaped ditch. The end walls are
// vertical. A footprint reaching past the extent makes a step down.
struct Trench {
  Footprint footprint;
  double depth = 1.0;
  double wall_run = 0.0;  // [m]
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

// A fresh bowl-shaped impact crater, added to the ground: a parabolic bowl
// `depth` below its rim crest, the rim `rim_height` above the surrounding
// ground, ejecta falling off as (R / r)^3 out to three radii (the profile
// used for small fresh lunar and Martian craters, e.g. Fassett & Thomson
// 2014).
struct Crater {
  double cx = 0.0;
  double cy = 0.0;
  double diameter = 2.0;     // rim crest to rim crest [m]
  double depth = 0.4;        // rim crest to floor [m]
  double rim_height = 0.08;  // above the pre-impact ground [m]

  double radius() const { return 0.5 * diameter; }
  double reach() const { return 1.5 * diameter; }  // ejecta ends at 3 R
  // Height added to the ground at (x, y) [m].
  double relief(double x, double y) const;
};

// Everything that defines a procedural terrain: ground (a plane, waves and
// craters) plus features, within an extent.
struct TerrainDescription {
  Box2 extent{-20.0, -10.0, 20.0, 50.0};
  double base_height = 0.0;
  Eigen::Vector2d gradient{0.0, 0.0};  // dz/dx, dz/dy of the plane
  std::vector<Wave> waves;
  std::vector<Crater> craters;
  std::vector<Feature> features;
};

// Analytic terrain: z = ground (plane + waves + craters), carved by
// trenches, raised by boxes, ramps and rocks (the highest wins). Heights
// are exact, not sampled.
class ProceduralTerrain : public Terrain {
 public:
  explicit ProceduralTerrain(TerrainDescription description);

  double height(double x, double y) const override;
  double maxHeightIn(const Box2& box) const override;
  Box2 extent() const override { return description_.extent; }

  // The ground alone (plane, waves, craters), without features.
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
  // Uniform bins over the extent listing the items (features or craters)
  // whose bounds overlap them.
  struct Bins {
    double size = 2.0;
    Box2 extent;
    int cols = 0, rows = 0;
    std::vector<std::vector<int>> items;

    void build(const Box2& extent, const std::vector<Box2>& bounds);
    const std::vector<int>& near(double x, double y) const;
    // Calls f(item) for every item listed in a bin overlapping `box`
    // (an item may come more than once).
    template <class F>
    void forEachIn(const Box2& box, F&& f) const;

   private:
    // The bins overlapping `box`, clamped to the grid: c0, c1, r0, r1.
    std::array<int, 4> range(const Box2& box) const;
  };
  double planeAndWaves(double x, double y) const;

  TerrainDescription description_;
  WaveSum wave_sum_;
  std::vector<double> feature_top_;  // absolute top height of each feature
  std::vector<Box2> feature_bounds_;
  Bins feature_bins_, crater_bins_;
};

}  // namespace ambler::sim
