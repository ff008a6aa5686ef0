#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "sensor/RangeImage.h"
#include "terrain/OccludingEdges.h"

namespace ambler::terrain {

// A pixel's second difference across scanlines within this many of its
// noise's standard deviations is taken as none (rowCurvature()): set a
// priori; on the tuning seeds no noisy map's RMSE moves by more than
// 0.01 mm with it (docs/elevation-maps.md).
inline constexpr double kCurvatureNoise = 3.0;

// What the locus search reads of one range image beyond its ranges,
// tabulated once per image: per pixel its point in the world and its reach,
// per quad of pixels whether it is a steep face or too sparse to interpolate
// and the sampling part of a cell's sigma, and per border column where the
// border scanline meets the ground. Cells outnumber quads, and neighbouring
// cells share them (docs/elevation-maps.md, Speed).
class LocusTables {
 public:
  // `max_sample_spacing_m` and `curved_rows` as LocusOptions::
  // max_sample_spacing_m and curved_between_scanlines.
  LocusTables(const sensor::RangeImage& image, const OccludingEdges& edges,
              double max_sample_spacing_m, bool curved_rows);

  // Per scanline, sin and cos of its scan angle phi.
  const std::vector<double>& sinPhi() const { return sin_phi_; }
  const std::vector<double>& cosPhi() const { return cos_phi_; }
  // The image's ranges, row-major, with NaN where a pixel has no return, so
  // that an interpolation that uses such a pixel is NaN without a test.
  const std::vector<double>& ranges() const { return range_; }
  // Per pixel, its point in the world (NaN without a return) and its
  // horizontal distance from the sensor [m].
  const std::vector<Eigen::Vector3f>& world() const { return world_; }
  const std::vector<float>& reach() const { return across_; }
  // The sensor reaches at least this far [m].
  double farthestReturn() const { return farthest_return_; }
  // Median world height of the image's points (every 4th row and column),
  // the sensor's height without any.
  double typicalHeight() const { return typical_height_; }

  // Per quad (its top-left pixel): its normal is steeper than 75 degrees.
  bool isSteepFace(int quad_row, int quad_col) const {
    return steep_[std::size_t(quad_row) * (cols_ - 1) + quad_col] != 0;
  }
  // The sampling part of the height sigma of a cell whose line crosses the
  // quad [m].
  double samplingSigma(int quad_row, int quad_col) const {
    return sampling_sigma_[std::size_t(quad_row) * (cols_ - 1) + quad_col];
  }
  // The quad's scanlines meet the ground farther apart than the limit.
  bool isSparse(int quad_row, int quad_col) const {
    return sparse_[std::size_t(quad_row) * (cols_ - 1) + quad_col] != 0;
  }

  // Per pixel, the second difference of the range across its scanline and
  // the two either side [m]; NaN on the border scanlines, next to a pixel
  // without a return, and where one of the four quads around the pixel is
  // an occluding edge or a steep face, across which the surface does not
  // go on; 0 where within kCurvatureNoise of its noise. Empty without
  // curved_rows.
  const std::vector<double>& rowCurvature() const { return row_curvature_; }
  // Per quad: its four pixels' second differences are finite and one is
  // not 0, so the surface across it is no chord (none without curved_rows).
  bool quadBends(int quad_row, int quad_col) const {
    return bends_[std::size_t(quad_row) * (cols_ - 1) + quad_col] != 0;
  }

  // Per image column, for the first (0) and the last (1) scanline: the
  // horizontal distance from the sensor at which it meets the ground [m],
  // NaN where the whole border has no ground; and the stretch beyond the
  // border's own ground, from its reach to one scanline step beyond, over
  // the pixel's footprint, which the scan saw but did not sample (NaN
  // without own ground).
  const std::vector<double>& borderReach(int border) const { return border_reach_[border]; }
  const std::vector<double>& borderOwnFrom(int border) const { return border_own_from_[border]; }
  const std::vector<double>& borderOwnTo(int border) const { return border_own_to_[border]; }

 private:
  // The least-squares plane z = f(x, y) of the 3 x 3 pixels of 2 x 2
  // quads: whether they lie on it within their noise, each pixel's offset
  // from it, and the sigma of such an offset [m].
  struct BlockPlane {
    bool planar = false;
    std::array<float, 9> offset{};
    double offset_noise = 0;
  };

  void tabulatePixels();
  std::vector<std::uint8_t> quadsNearEdges(const OccludingEdges& edges) const;
  void tabulateSteepFaces();
  void tabulateSamplingSigma(const std::vector<std::uint8_t>& near_edge);
  BlockPlane fitBlockPlane(int r, int c) const;
  // z00 - z01 - z10 + z11 of quad (r, c)'s pixels: small against their
  // height range on a plane, as large on a bump.
  double quadTwist(int r, int c) const {
    const std::size_t p = std::size_t(r) * g_.cols + c, q = p + g_.cols;
    return world_[p].z() - world_[p + 1].z() - world_[q].z() + world_[q + 1].z();
  }
  void markSparseQuads(double max_spacing_m);
  void tabulateRowCurvature(const OccludingEdges& edges);
  // A run of border columns with continuous ranges, [first, last].
  struct BorderSurface {
    int first, last;
  };
  void findBorderGround(const OccludingEdges& edges);
  void findOwnBorderGround(int b, const OccludingEdges& edges);
  std::vector<BorderSurface> borderSurfaces(int border, const OccludingEdges& edges) const;
  static void fillFromNearestGround(std::vector<double>& reach,
                                    const std::vector<BorderSurface>& surfaces);
  void reachAcrossObstacles(int border, const std::vector<BorderSurface>& surfaces,
                            std::vector<double>& reach) const;
  bool hasReturn(int r, int c) const { return image_.hasReturn(r, c); }
  double reachAt(int row, int col) const { return across_[std::size_t(row) * g_.cols + col]; }

  const sensor::RangeImage& image_;
  const sensor::ScanGeometry& g_;
  int cols_ = 0;
  Eigen::Vector3d origin_;  // the sensor in the world
  std::vector<double> sin_phi_, cos_phi_;
  std::vector<double> range_;
  double farthest_return_ = 0.0;
  std::vector<Eigen::Vector3f> world_;
  std::vector<float> across_;
  double typical_height_ = 0.0;
  std::vector<std::uint8_t> steep_;
  std::vector<double> sampling_sigma_;
  std::vector<std::uint8_t> sparse_;
  std::vector<double> row_curvature_;
  std::vector<std::uint8_t> bends_;
  std::array<std::vector<double>, 2> border_reach_, border_own_from_, border_own_to_;
};

}  // namespace ambler::terrain
