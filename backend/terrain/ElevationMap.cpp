#include "terrain/ElevationMap.h"

#include <cmath>
#include <stdexcept>
#include <utility>

namespace ambler::terrain {

namespace {
Layer filled(const GridSpec& grid, float value) {
  return Layer::Constant(grid.rows, grid.cols, value);
}
}  // namespace

ElevationMap::ElevationMap(const GridSpec& grid, std::string frame)
    : grid_(grid),
      frame_(std::move(frame)),
      elevation_(filled(grid, NAN)),
      sigma_(filled(grid, NAN)),
      state_(filled(grid, float(CellState::kUnknown))),
      count_(filled(grid, 0.0f)) {}

bool ElevationMap::hasLayer(const std::string& name) const {
  return name == layer::kElevation || name == layer::kSigma || name == layer::kState ||
         name == layer::kCount || extra_.count(name) > 0;
}

Layer& ElevationMap::addLayer(const std::string& name, float value) {
  Layer& l = hasLayer(name) ? layer(name) : extra_[name];
  l = filled(grid_, value);
  return l;
}

Layer& ElevationMap::layer(const std::string& name) {
  return const_cast<Layer&>(std::as_const(*this).layer(name));
}

const Layer& ElevationMap::layer(const std::string& name) const {
  if (name == layer::kElevation) return elevation_;
  if (name == layer::kSigma) return sigma_;
  if (name == layer::kState) return state_;
  if (name == layer::kCount) return count_;
  const auto it = extra_.find(name);
  if (it == extra_.end()) throw std::out_of_range("elevation map has no layer '" + name + "'");
  return it->second;
}

std::vector<std::string> ElevationMap::layerNames() const {
  std::vector<std::string> names{layer::kElevation, layer::kSigma, layer::kState, layer::kCount};
  for (const auto& [name, l] : extra_) names.push_back(name);
  return names;
}

void ElevationMap::setKnown(int r, int c, double elevation, double sigma, float observations) {
  setHeight(r, c, CellState::kKnown, elevation, sigma, observations);
}

void ElevationMap::setHeight(int r, int c, CellState state, double elevation, double sigma,
                             float observations) {
  if (state != CellState::kKnown && state != CellState::kOblique)
    throw std::invalid_argument("only a known or an oblique cell has a height");
  elevation_(r, c) = float(elevation);
  sigma_(r, c) = float(sigma);
  state_(r, c) = float(state);
  count_(r, c) = observations;
}

void ElevationMap::setUnobserved(int r, int c, CellState state) {
  elevation_(r, c) = NAN;
  sigma_(r, c) = NAN;
  state_(r, c) = float(state);
}

int ElevationMap::countOf(CellState state) const {
  return int((state_.array() == float(state)).count());
}

int ElevationMap::knownCount() const { return countOf(CellState::kKnown); }

}  // namespace ambler::terrain
