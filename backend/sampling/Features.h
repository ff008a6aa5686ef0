#pragma once

#include <cstdint>
#include <vector>

#include "sensor/StriperImage.h"

namespace ambler::sampling {

// cmu-1990 sampling paper §2: three kinds of local evidence that an object
// is near, none expected to close around it.
enum FeatureKind : std::uint8_t {
  kShadow = 1,      // no measurement: lit but hidden from the camera, or the reverse
  kRangeEdge = 2,   // surface discontinuity: an edge of r = |p - camera|
  kNormalEdge = 4,  // concave surface-normal discontinuity: where an object meets the terrain
};

struct FeatureOptions {
  int window_px = 31;            // side of the window of the local edge distribution
  double edge_sigmas = 3.0;      // an edge exceeds the local mean by this many local stds
  double min_edge_m = 0.002;     // and this range step per pixel, whatever the distribution
  double smooth_px = 0.7;        // Gaussian sigma on X, Y, Z, and again on the normals
  double normal_dot_max = 0.95;  // normals less aligned than this (about 18 deg) ...
  int normal_step_px = 2;        // ... this many pixels apart (smoothing spreads a crease)
  int min_region_px = 4;         // smaller connected groups of edge pixels are noise
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const FeatureOptions& options);

struct FeatureMap {
  int rows = 0, cols = 0;
  std::vector<std::uint8_t> kinds;  // FeatureKind bits per pixel, row-major
  std::vector<int> region;          // connected feature region per pixel, -1 for none
  int region_count = 0;

  bool isFeature(int r, int c) const {
    return r < 0 || c < 0 || r >= rows || c >= cols || kinds[std::size_t(r) * cols + c] != 0;
  }
  std::uint8_t kindAt(int r, int c) const { return kinds[std::size_t(r) * cols + c]; }
  int count(FeatureKind kind) const;
};

// Throws std::invalid_argument for an unusable image (sensor::findProblem).
FeatureMap extractFeatures(const sensor::StriperImage& image, const FeatureOptions& options = {});

}  // namespace ambler::sampling
