#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/GridSpec.h"

namespace ambler::terrain {

// What a map knows about a cell (krotkov1989 §3.2, fig. 6). The codes are
// those of state.tif (docs/formats.md); the simulator's truth uses the
// first three. An oblique cell has a height, but one interpolated between
// samples of ground seen at a grazing angle or beside a shadow, where what
// lies between them was barely seen, if at all: good for matching scans and for clearances
// (the unseen ground lies below the line of sight), not to stand on.
enum class CellState : std::uint8_t { kKnown = 0, kUnknown = 1, kShadow = 2, kOblique = 3 };

inline bool hasHeight(CellState s) { return s == CellState::kKnown || s == CellState::kOblique; }

// One layer: a float per cell, row-major like the GridSpec (row = y).
using Layer = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Names of the layers every map has.
namespace layer {
inline const std::string kElevation = "elevation";  // [m], NaN unless known or oblique
inline const std::string kSigma = "sigma";  // elevation std. dev. [m], NaN unless known or oblique
inline const std::string kState = "state";  // CellState code
inline const std::string kCount = "count";  // observations fused into the cell
}  // namespace layer

// An elevation map in the style of grid_map: one grid, several named float
// layers of the same size, the frame the heights are expressed in. A new map
// knows nothing: every cell unknown, no observations.
class ElevationMap {
 public:
  ElevationMap() = default;
  explicit ElevationMap(const GridSpec& grid, std::string frame = "world");

  const GridSpec& grid() const { return grid_; }
  const std::string& frame() const { return frame_; }

  bool hasLayer(const std::string& name) const;
  // Adds (or resets) a layer filled with `value`.
  Layer& addLayer(const std::string& name, float value);
  // Throws std::out_of_range naming the layer when it does not exist.
  Layer& layer(const std::string& name);
  const Layer& layer(const std::string& name) const;
  std::vector<std::string> layerNames() const;

  CellState state(int r, int c) const { return CellState(std::uint8_t(state_(r, c))); }
  bool isKnown(int r, int c) const { return state(r, c) == CellState::kKnown; }
  // Known or oblique.
  bool hasHeight(int r, int c) const { return terrain::hasHeight(state(r, c)); }
  float elevation(int r, int c) const { return elevation_(r, c); }
  float sigma(int r, int c) const { return sigma_(r, c); }
  float count(int r, int c) const { return count_(r, c); }

  // A known cell from one or more observations.
  void setKnown(int r, int c, double elevation, double sigma, float observations = 1);
  // A known or oblique cell.
  void setHeight(int r, int c, CellState state, double elevation, double sigma,
                 float observations = 1);
  // An unknown or shadow cell: elevation and sigma become NaN.
  void setUnobserved(int r, int c, CellState state);

  int knownCount() const;
  int countOf(CellState state) const;

 private:
  GridSpec grid_;
  std::string frame_ = "world";
  // The four layers every map has are members so that copies stay valid and
  // per-cell access costs no lookup; further layers live in extra_.
  Layer elevation_, sigma_, state_, count_;
  std::map<std::string, Layer> extra_;
};

}  // namespace ambler::terrain
