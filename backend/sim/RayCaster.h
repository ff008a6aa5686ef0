#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "sim/Terrain.h"

namespace ambler::sim {

struct RayCasterOptions {
  double cell_size = 0.5;  // bins of the upper-bound grid [m]
  double step = 0.02;      // marching step near the ground [m]; features
                           // thinner than this may be missed
  double tolerance = 0.0;  // bisection stops at this bracket [m]; 0: machine precision
};

// Where a ray first meets the ground: the simulator's scanner and the
// evaluations' truth each use one, and they are kept independent
// (RayCaster and EmbreeCaster) so that a bug in one cannot hide in both.
class FirstHit {
 public:
  virtual ~FirstHit() = default;
  // Distance along the unit `direction` from `origin` to the first ground
  // hit no farther than max_range, or nothing.
  virtual std::optional<double> cast(const Eigen::Vector3d& origin,
                                     const Eigen::Vector3d& direction, double max_range) const = 0;
  virtual const Terrain& terrain() const = 0;
};

// Casts rays against a Terrain. Space above a per-bin upper bound of the
// terrain is skipped; near the ground the ray marches in fixed steps and the
// first sign change of (ray z - ground z) is refined by bisection, so hits
// are exact to far below a millimetre on any continuous or stepped surface.
class RayCaster final : public FirstHit {
 public:
  explicit RayCaster(const Terrain& terrain, RayCasterOptions options = {});

  // Distance along the unit `direction` from `origin` to the first ground
  // hit no farther than max_range, or nothing (sky, off the terrain, or an
  // origin below the ground).
  std::optional<double> cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                             double max_range) const override;

  const Terrain& terrain() const override { return terrain_; }

 private:
  double groundGap(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t) const;

  const Terrain& terrain_;
  RayCasterOptions options_;
  Box2 extent_;
  int cols_ = 0, rows_ = 0;
  std::vector<double> bin_max_;
  double top_ = 0.0;  // the highest bin's bound [m]
};

}  // namespace ambler::sim
