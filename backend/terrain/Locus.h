#pragma once

#include <vector>

#include "core/GridSpec.h"
#include "sensor/RangeImage.h"
#include "terrain/ElevationMap.h"
#include "terrain/OccludingEdges.h"

namespace ambler::terrain {

struct LocusOptions {
  // The binary search along a locus stops when its bracket is narrower than
  // this [rad], and the root is interpolated linearly across the last
  // bracket; 0 means 1/4 of the scanline spacing, two levels. A third level
  // would lower `eval elevation`'s locus RMSE by 0.02 mm (0.04489 to
  // 0.04487 m) for 1.4 ms more of a 21 ms map.
  double epsilon_rad = 0.0;
  OccludingEdgeOptions edges;
  // Cells between samples that meet the ground farther apart than this are
  // unknown (krotkov1989 §3.2: a shadow far off may be no larger than the
  // distance between data points). The Ambler's foot is 0.3 m across: a
  // hole it could step into fits between sparser samples. INFINITY: off.
  double max_sample_spacing_m = 0.3;
  // Cells of quads whose range noise could hide a gap in the ground this
  // long from the occluding-edge test are oblique: such a shadow makes a
  // range jump about as long, which the test takes for noise while it is
  // within edges.noise_sigmas sqrt(2) k rho^2 (a pair's allowance). Their
  // heights were measured, but a hole the foot could step into may lie
  // between them unseen: the sparse-sample rule above for noisy ranges
  // (docs/elevation-maps.md). Positive; INFINITY: off.
  double max_gap_hidden_by_noise_m = 0.3;
  // Shadow cells closer to the occluder's last sample than this many of the
  // samples' steps before it are unknown instead: the edge may lie anywhere
  // up to the next step, and ground before it was seen, if at all, at the
  // last samples' grazing angle (docs/elevation-maps.md). 0: off.
  double undecided_before_shadow = 0.5;
  // Behind a crest the shadow ends somewhere between where the ray through
  // the occluder's last sample meets the ground beyond (extended back as a
  // line through its first two samples) and the first sample on it. Shadow
  // cells in this share of that stretch, nearest that sample, are unknown
  // instead (docs/elevation-maps.md). 0: off.
  double undecided_shadow_far_end = 0.5;
  // An occluder is a crest, not a face, when the segment through its last
  // two samples lies within this angle of the ray through the last [deg]:
  // beyond a face's last sample the occluder may go on unseen.
  double crest_max_angle_deg = 60.0;
  // Between the bracketing scanlines the surface follows a Catmull-Rom
  // spline through them and the scanlines either side, not their chord: far
  // ground bends between scanlines that meet it tens of centimetres apart.
  // Second differences within three standard deviations of their noise
  // count as none, so under noise nearly every cell keeps the chord, and
  // so does a kink (the bracket's two of opposite signs, or one alone).
  // Off: the paper's bilinear surface.
  bool curved_between_scanlines = true;
  // Known cells beside a shadow across the line of sight (its sides, where
  // interpolation meets unseen ground) become oblique
  // (docs/elevation-maps.md).
  bool oblique_shadow_sides = true;
  // And so do the known cells one and two steps beyond a shadow along the
  // line of sight, where a hidden floor meets the far wall's interpolated
  // face.
  bool oblique_shadow_far_ends = true;
  // Cells with a height beside a face across the line of sight, whose
  // heights lie beyond this many standard deviations of the face band's
  // middle, have the band in their sigma (widenSigmaBesideFaces). 0: off.
  double face_side_noise_sigmas = 3.0;
  int threads = 0;  // OpenMP threads; 0 means the OpenMP default
};

// krotkov1989 §3.1-3.3: the elevation map of one range image by the locus
// algorithm, generalised to any sensor pose (footnote 4). For each cell the
// vertical world line through its centre is traced in image space: the two
// scanlines between which (locus range - image range) changes sign bracket
// the surface, a binary search on phi narrows the bracket to epsilon, a
// linear interpolation across it places the root, and the image is
// interpolated from the four pixels around the intersection
// (Lagrange, i.e. bilinear in phi and theta). A cell whose intersection lies
// in a quad of pixels across an occluding edge is shadow; a cell whose line
// leaves the image, or meets pixels without returns, is unknown; one in a
// quad of ground seen at a grazing angle (OccludingEdgeOptions::
// mark_grazing), or whose noise could hide a gap, is oblique. Elevations
// are in the world frame of image.sensor_to_world; sigma follows
// docs/elevation-uncertainty.md.
ElevationMap buildLocusMap(const sensor::RangeImage& image, const GridSpec& grid,
                           const LocusOptions& options = {});

// A face's position across the line of sight is known to no better than
// the spacing of the image's columns, about a cell: between two columns,
// one on a box's face and one passing beside the box, the interpolated
// ground runs on into the box, and a cell there is known at the ground's
// height, with a sigma of millimetres, though the box's top stands over its
// centre. So a face cell (`face_noise`, row-major: the sigma of a cell
// whose height is the middle of a band along a face, without the band;
// NaN for the rest), whose height spans z +- sqrt(3) sigma, widens the
// sigma of its neighbours across the line of sight from `sensor` whose
// height lies farther from its middle than `noise_sigmas` of their
// noise: the spread from the neighbour's height to the band's far end,
// taken as uniform. Along the line of sight the ranges measure the face's
// distance, and the band covers the cells within their noise of it.
// Heights and states do not change. noise_sigmas <= 0: off.
void widenSigmaBesideFaces(ElevationMap& map, const std::vector<float>& face_noise,
                           const Eigen::Vector2d& sensor, double noise_sigmas);

// The range beyond which noise k (sigma = k rho^2) could hide a gap of
// options.max_gap_hidden_by_noise_m from the edge test, so that the map
// has the ground there as oblique [m]; INFINITY without noise.
double rangeWhereNoiseMayHideGap(double k, const LocusOptions& options);

}  // namespace ambler::terrain
