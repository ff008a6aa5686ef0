#pragma once

#include <cstdint>
#include <vector>

#include "sensor/RangeImage.h"

namespace ambler::terrain {

// krotkov1989 §3.2: a range shadow is an occluding edge in the range image.
// A continuous surface seen at grazing angle alpha changes range by about
// rho * delta / tan(alpha) between pixels delta radians apart, so a larger
// jump between neighbouring pixels is a discontinuity: either an occluding
// edge or a surface seen so obliquely that it is as good as hidden. Range
// noise (sigma = k rho^2 per pixel) widens the threshold.
struct OccludingEdgeOptions {
  double min_grazing_deg = 10.0;  // jumps no steeper than this grazing angle are continuous
  double step_ratio = 3.0;        // and so are jumps below this many times the occluder's slope
  double noise_sigmas = 4.0;      // noise allowance, in std. dev. of the jump
  // A jump beyond only this smaller allowance is an edge too when a jump of
  // the same kind continues it in a neighbouring pixel (hysteresis, as in
  // Canny's detector): an occluding edge runs along the image, noise does
  // not. Equal to noise_sigmas turns it off; 2 finds more of the terrain
  // families' shadows for a little precision (docs/elevation-maps.md).
  double weak_noise_sigmas = 2.0;
  // Quads with a pair steeper than min_grazing_deg, beyond a noise
  // allowance, that is no edge are grazing (quadIsGrazing), and the locus
  // map makes their cells oblique: they keep their heights for matching
  // scans, but nobody stands on them. Off, those cells are known.
  bool mark_grazing = true;
  // The allowance, in std. dev. of the jump; at most the weak allowance
  // (the constructor throws std::invalid_argument otherwise).
  double grazing_noise_sigmas = 1.5;
  // Hysteresis again: a pair beyond only this smaller allowance is grazing
  // when a neighbouring pair of the same kind along the image is grazing or
  // an edge, for ground seen obliquely runs along the image like an edge.
  // At most grazing_noise_sigmas; equal turns it off (docs/elevation-maps.md).
  double weak_grazing_noise_sigmas = 0.0;
  // And a pair whose jump is steeper than ground seen at this larger
  // grazing angle (beyond the grazing allowance), when such a neighbour
  // continues it: a swell's back slope seen just above min_grazing_deg,
  // beside where it falls below, hides dips between its samples. At most
  // min_grazing_deg turns it off (docs/elevation-maps.md).
  double weak_grazing_deg = 13.0;
  // And a pair seen under weak_grazing_deg (beyond the grazing allowance)
  // whose next pair farther along its image column is seen this much more
  // steeply, beyond the grazing allowance of that pair's noise: the ground
  // turns back toward the sensor behind a receding stretch, the pocket
  // behind a swell's back. Pairs across scanlines only, whose column runs
  // along the line of sight. 0 turns it off (docs/elevation-maps.md).
  double concave_turn_deg = 4.0;
  // Under heavy noise one pair cannot tell ground seen just beyond the
  // grazing bound from noise, and such ground stays known, though relief
  // hides parts of it. The range step averaged over this many scanlines
  // can: its noise falls as one over their number. Quads whose averaged
  // step is beyond the bound by more than the allowance (std. dev. of the
  // average) are grazing too. 0 turns it off; otherwise at least 2, an odd
  // number counting as the even one below it (docs/elevation-maps.md).
  int grazing_baseline_rows = 16;
  double grazing_baseline_noise_sigmas = 2.0;
};

// The discontinuities of one range image, indexed by the image's quads: quad
// (r, c) is the square of pixels (r, c), (r, c+1), (r+1, c), (r+1, c+1)
// that interpolation draws from. A quad is an edge quad when any two of its
// pixels (sides or diagonals) are discontinuous. Pixels without a return
// are not edges; they make interpolation impossible instead.
class OccludingEdges {
 public:
  OccludingEdges() = default;
  OccludingEdges(const sensor::RangeImage& image, const OccludingEdgeOptions& options = {});

  bool quadIsEdge(int r, int c) const { return quadFlags(r, c) & kEdgeQuad; }
  // A quad with a pair steeper than min_grazing_deg that is not an edge: a
  // surface seen that obliquely, or an edge the noise hides. Either way
  // what lies between its samples was barely seen, if at all.
  bool quadIsGrazing(int r, int c) const { return quadFlags(r, c) == kGrazingQuad; }
  // Pixels on either side of a discontinuity (for display and tests).
  bool pixelIsEdge(int r, int c) const { return pixel_[std::size_t(r) * cols_ + c] & kEdgePixel; }
  // Pixels (r, c) and (r, c + 1) are discontinuous.
  bool rightPairIsEdge(int r, int c) const {
    return pixel_[std::size_t(r) * cols_ + c] & kRightPairEdge;
  }
  int edgePixelCount() const;

 private:
  static constexpr std::uint8_t kEdgeQuad = 1, kGrazingQuad = 2;
  static constexpr std::uint8_t kEdgePixel = 1, kRightPairEdge = 2;
  std::uint8_t quadFlags(int r, int c) const { return quad_[std::size_t(r) * (cols_ - 1) + c]; }
  void markGrazingBaselines(const std::vector<float>& range, const std::vector<double>& row_sep,
                            double inv_tan_grazing, double k, int rows, double noise_sigmas,
                            double pair_noise_sigmas);
  // Kinds as the levels' bits: 0 along a scanline, 1 across scanlines, 2
  // and 3 the diagonals.
  void markQuadsOfPair(int r, int c, int kind, std::uint8_t flag);
  void markEdgePair(int r, int c, int kind);

  int rows_ = 0, cols_ = 0;
  std::vector<std::uint8_t> pixel_;
  std::vector<std::uint8_t> quad_;  // (rows - 1) x (cols - 1)
};

}  // namespace ambler::terrain
