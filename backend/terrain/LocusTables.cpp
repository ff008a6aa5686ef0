#include "terrain/LocusTables.h"

#include <algorithm>
#include <cmath>

namespace ambler::terrain {

namespace {

// Surfaces steeper than 75 degrees are faces: the height of a cell on them is
// undetermined.
constexpr double kSteepFaceCos = 0.26;

}  // namespace

LocusTables::LocusTables(const sensor::RangeImage& image, const OccludingEdges& edges,
                         double max_sample_spacing_m, bool curved_rows)
    : image_(image), g_(image.geometry), cols_(image.geometry.cols) {
  origin_ = image.sensor_to_world.translation();
  for (int r = 0; r < g_.rows; ++r) {
    sin_phi_.push_back(std::sin(g_.phi(r)));
    cos_phi_.push_back(std::cos(g_.phi(r)));
  }
  tabulatePixels();
  tabulateSteepFaces();
  tabulateSamplingSigma(quadsNearEdges(edges));
  markSparseQuads(max_sample_spacing_m);
  if (curved_rows)
    tabulateRowCurvature(edges);
  else
    bends_.assign(std::size_t(g_.rows - 1) * (g_.cols - 1), 0);
  findBorderGround(edges);
}

void LocusTables::tabulateRowCurvature(const OccludingEdges& edges) {
  const int cols = g_.cols, quad_cols = cols - 1;
  // A second difference within kCurvatureNoise of its own noise (three
  // ranges', sqrt(6) times one's) is taken as none: only the ground's bends
  // beyond the noise move the surface off the chord. NaN stays NaN.
  const double sigmas = kCurvatureNoise * std::sqrt(6.0), k = image_.range_sigma_k;
  row_curvature_.assign(range_.size(), NAN);
  for (int r = 1; r + 1 < g_.rows; ++r) {
    const double* range = &range_[std::size_t(r) * cols];
    double* out = &row_curvature_[std::size_t(r) * cols];
    for (int c = 0; c < cols; ++c) {
      const double d = range[c - cols] - 2 * range[c] + range[c + cols];
      out[c] = std::abs(d) <= sigmas * sensor::rangeSigma(range[c], k) ? 0.0 : d;
    }
  }
  // Nor does the surface go on across an edge or a face: NaN at its pixels.
  for (int r = 0; r + 1 < g_.rows; ++r)
    for (int c = 0; c < quad_cols; ++c)
      if (edges.quadIsEdge(r, c) || isSteepFace(r, c)) {
        double* d = &row_curvature_[std::size_t(r) * cols + c];
        d[0] = d[1] = d[cols] = d[cols + 1] = NAN;
      }
  bends_.assign(std::size_t(g_.rows - 1) * quad_cols, 0);
  for (int r = 0; r + 1 < g_.rows; ++r) {
    const double* d = &row_curvature_[std::size_t(r) * cols];
    std::uint8_t* bends = &bends_[std::size_t(r) * quad_cols];
    for (int c = 0; c < quad_cols; ++c)  // false for NaN
      bends[c] =
          std::abs(d[c]) + std::abs(d[c + 1]) + std::abs(d[c + cols]) + std::abs(d[c + cols + 1]) >
          0;
  }
}

void LocusTables::tabulatePixels() {
  range_.assign(std::size_t(g_.rows) * g_.cols, NAN);
  for (int r = 0; r < g_.rows; ++r)
    for (int c = 0; c < g_.cols; ++c)
      if (hasReturn(r, c)) {
        range_[std::size_t(r) * g_.cols + c] = image_.at(r, c);
        farthest_return_ = std::max(farthest_return_, double(image_.at(r, c)));
      }
  // Every pixel's point in the world (eq. 1 and the pose), from the
  // per-row and per-column sines instead of three sin/cos per pixel.
  const Eigen::Matrix3d rotation = image_.sensor_to_world.linear();
  world_.assign(std::size_t(g_.rows) * g_.cols, Eigen::Vector3f::Constant(NAN));
  for (int c = 0; c < g_.cols; ++c) {
    const double st = std::sin(g_.theta(c)), ct = std::cos(g_.theta(c));
    for (int r = 0; r < g_.rows; ++r)
      if (hasReturn(r, c)) {
        const Eigen::Vector3d direction(st, cos_phi_[r] * ct, sin_phi_[r] * ct);
        world_[std::size_t(r) * g_.cols + c] =
            (origin_ + image_.at(r, c) * (rotation * direction)).cast<float>();
      }
  }
  across_.resize(world_.size());
  for (std::size_t i = 0; i < world_.size(); ++i)
    across_[i] = (world_[i].head<2>() - origin_.head<2>().cast<float>()).norm();
  std::vector<double> z;
  for (int r = 0; r < g_.rows; r += 4)
    for (int c = 0; c < g_.cols; c += 4)
      if (hasReturn(r, c)) z.push_back(world_[std::size_t(r) * g_.cols + c].z());
  typical_height_ = origin_.z();
  if (!z.empty()) {
    std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
    typical_height_ = z[z.size() / 2];
  }
}

// The edge quads dilated by one quad, along rows and then along columns.
std::vector<std::uint8_t> LocusTables::quadsNearEdges(const OccludingEdges& edges) const {
  const int quad_rows = g_.rows - 1, quad_cols = g_.cols - 1;
  std::vector<std::uint8_t> across(std::size_t(quad_rows) * quad_cols, 0);
  for (int r = 0; r < quad_rows; ++r)
    for (int c = 0; c < quad_cols; ++c)
      across[std::size_t(r) * quad_cols + c] = edges.quadIsEdge(r, std::max(c - 1, 0)) ||
                                               edges.quadIsEdge(r, c) ||
                                               edges.quadIsEdge(r, std::min(c + 1, quad_cols - 1));
  std::vector<std::uint8_t> near_edge(across.size(), 0);
  for (int r = 0; r < quad_rows; ++r)
    for (int c = 0; c < quad_cols; ++c) {
      const std::size_t i = std::size_t(r) * quad_cols + c;
      near_edge[i] = across[i] || across[std::size_t(std::max(r - 1, 0)) * quad_cols + c] ||
                     across[std::size_t(std::min(r + 1, quad_rows - 1)) * quad_cols + c];
    }
  return near_edge;
}

// A vertical line running along a steep face (a box side, a trench wall)
// meets it over a long stretch: its crossing, and so the cell's height, is
// not determined. The quad's normal, from its diagonals, tells.
void LocusTables::tabulateSteepFaces() {
  const int cols = g_.cols, quad_rows = g_.rows - 1, quad_cols = cols - 1;
  const auto at = [&](std::size_t pixel) -> Eigen::Vector3d {
    return world_[pixel].cast<double>();
  };
  steep_.assign(std::size_t(quad_rows) * quad_cols, 0);
  for (int r = 0; r < quad_rows; ++r)
    for (int c = 0; c < quad_cols; ++c) {
      const std::size_t p = std::size_t(r) * cols + c, q = p + cols;
      const Eigen::Vector3d n = (at(q + 1) - at(p)).cross(at(p + 1) - at(q));
      steep_[std::size_t(r) * quad_cols + c] = std::abs(n.z()) < kSteepFaceCos * n.norm();
    }
}

// Sampling: the image only knows the surface at its pixels, so a cell's
// height is bounded by the heights of the pixels around its crossing, taken
// as uniform in between (std. dev. = spread / sqrt(12)): the quad's four
// pixels, or the 4 x 4 around it where `near_edge` (within a pixel of an
// occluding edge), where the cell may belong to either surface.
void LocusTables::tabulateSamplingSigma(const std::vector<std::uint8_t>& near_edge) {
  const int cols = g_.cols, quad_rows = g_.rows - 1, quad_cols = cols - 1;
  // Per quad, the lowest and highest of its four pixels, those without a
  // return left out (as -+infinity).
  std::vector<float> lo(world_.size()), hi(world_.size());
  for (std::size_t i = 0; i < world_.size(); ++i) {
    const float z = world_[i].z();
    lo[i] = std::isnan(z) ? INFINITY : z, hi[i] = std::isnan(z) ? -INFINITY : z;
  }
  const std::size_t quad_pixels = world_.size() - cols - 1;  // the quads' top-left pixels
  for (std::size_t i = 0; i < quad_pixels; ++i) {
    lo[i] = std::min(std::min(lo[i], lo[i + 1]), std::min(lo[i + cols], lo[i + cols + 1]));
    hi[i] = std::max(std::max(hi[i], hi[i + 1]), std::max(hi[i + cols], hi[i + cols + 1]));
  }
  sampling_sigma_.assign(std::size_t(quad_rows) * quad_cols, 0.0);
  const double k = image_.range_sigma_k, sensor_z = origin_.z();
  // A plane is fitted per 2 x 2 quads (quad rows and columns r0, r0 + 1
  // for even r0), to their 3 x 3 pixels, when one of them first needs it.
  std::vector<BlockPlane> planes(std::size_t(quad_cols + 1) / 2);
  std::vector<int> fitted_for(planes.size(), -1);
  for (int r = 0; r < quad_rows; ++r) {
    const int r0 = r - r % 2;
    const bool inner_row = r0 + 2 < g_.rows;
    for (int c = 0; c < quad_cols; ++c) {
      const std::size_t quad = std::size_t(r) * quad_cols + c;
      double low = lo[std::size_t(r) * cols + c], high = hi[std::size_t(r) * cols + c];
      if (near_edge[quad])
        for (int nr = std::max(r - 1, 0); nr <= std::min(r + 1, quad_rows - 1); ++nr)
          for (int nc = std::max(c - 1, 0); nc <= std::min(c + 1, quad_cols - 1); ++nc) {
            low = std::min(low, double(lo[std::size_t(nr) * cols + nc]));
            high = std::max(high, double(hi[std::size_t(nr) * cols + nc]));
          }
      if (!(high > low)) continue;
      // The part of the spread that the pixels' own height noise explains
      // (about 2 sigma for four samples; k rho^2 times the ray's vertical
      // part each) is already in the noise term and is taken off.
      const double height_noise = k * image_.at(r, c) * std::abs(sensor_z - low);
      double excess = std::max(high - low - 2 * height_noise, 0.0);
      // On a plane the interpolation is exact and the quad's height range is
      // the plane's rise, not an error: where the pixels around it lie on a
      // plane within their noise, the range about that plane counts. Only
      // where the range is large enough to matter (beyond three height
      // sigmas: a term of a third of the noise, less in quadrature).
      const int c0 = c - c % 2, group = c0 / 2;
      if (inner_row && c0 + 2 < cols && !near_edge[quad] && excess > height_noise &&
          std::abs(quadTwist(r, c)) < 0.5 * (high - low)) {
        if (fitted_for[group] != r0) planes[group] = fitBlockPlane(r0, c0), fitted_for[group] = r0;
        const BlockPlane& plane = planes[group];
        if (plane.planar) {
          const int i = 3 * (r - r0) + c - c0;
          const float* d = &plane.offset[std::size_t(i)];
          const float least = std::min(std::min(d[0], d[1]), std::min(d[3], d[4]));
          const float most = std::max(std::max(d[0], d[1]), std::max(d[3], d[4]));
          excess = std::min(excess, std::max(most - least - 2 * plane.offset_noise, 0.0));
        }
      }
      sampling_sigma_[quad] = excess / std::sqrt(12.0);
    }
  }
}

// The plane of the 3 x 3 pixels from (r, c): planar when their rms offset
// from it is at most three sigmas of a pixel's offset and a millimetre
// (and every one has a return). A pixel's offset moves by the range noise
// times how far a step along its ray leaves the plane. In floats about the
// middle pixel: the block spans at most a few metres.
LocusTables::BlockPlane LocusTables::fitBlockPlane(int r, int c) const {
  BlockPlane plane;
  const Eigen::Vector3f o = world_[std::size_t(r + 1) * g_.cols + c + 1];
  std::array<Eigen::Vector3f, 9> p;
  float x = 0, y = 0, z = 0, xx = 0, xy = 0, yy = 0, xz = 0, yz = 0, zz = 0;
  for (int i = 0; i < 9; ++i) {
    const Eigen::Vector3f& q = p[std::size_t(i)] =
        world_[std::size_t(r + i / 3) * g_.cols + c + i % 3] - o;
    x += q.x(), y += q.y(), z += q.z();
    xx += q.x() * q.x(), xy += q.x() * q.y(), yy += q.y() * q.y();
    xz += q.x() * q.z(), yz += q.y() * q.z(), zz += q.z() * q.z();
  }
  const float mx = x / 9, my = y / 9, mz = z / 9;
  xx -= x * mx, xy -= x * my, yy -= y * my, xz -= x * mz, yz -= y * mz, zz -= z * mz;
  const float det = xx * yy - xy * xy;
  if (!(det > 1e-9f)) return plane;
  const float a = (xz * yy - yz * xy) / det, b = (yz * xx - xz * xy) / det;
  const Eigen::Vector3d ray = o.cast<double>() - origin_;
  plane.offset_noise =
      image_.range_sigma_k * ray.norm() * std::abs(ray.z() - a * ray.x() - b * ray.y());
  const double max_rms = 3 * plane.offset_noise + 0.001;
  plane.planar = zz - a * xz - b * yz <= 9 * max_rms * max_rms;
  for (int i = 0; i < 9; ++i) {
    const Eigen::Vector3f& q = p[std::size_t(i)];
    plane.offset[std::size_t(i)] = q.z() - mz - a * (q.x() - mx) - b * (q.y() - my);
  }
  return plane;
}

// krotkov1989 §3.2, note 5: far off, a shadow may be no larger than the
// distance between data points, and the interpolation then spans it as if
// it were ground. A quad whose scanlines meet the ground farther apart than
// `max_spacing_m` (horizontally, at either of its columns) is sparse: what
// lies between its samples is not known. The spacing is the mean step over
// four scanlines around the quad, less three standard deviations of the
// range noise in that mean, so that noise does not make dense samples look
// sparse.
void LocusTables::markSparseQuads(double max_spacing_m) {
  const int quad_rows = g_.rows - 1, quad_cols = g_.cols - 1;
  sparse_.assign(std::size_t(quad_rows) * quad_cols, 0);
  if (!std::isfinite(max_spacing_m)) return;
  auto spacing = [&](int quad_row, int c) {
    int a = std::max(quad_row - 1, 0), b = std::min(quad_row + 2, g_.rows - 1);
    auto at = [&](int r) { return reachAt(r, c); };
    if (std::isnan(at(a))) a = quad_row;
    if (std::isnan(at(b))) b = quad_row + 1;
    const double noise = sensor::rangeSigma(image_.at(quad_row, c), image_.range_sigma_k);
    return (std::abs(at(b) - at(a)) - 3 * std::sqrt(2.0) * noise) / (b - a);
  };
  std::vector<std::uint8_t> column_sparse(std::size_t(g_.cols));  // per pixel column of a quad row
  for (int r = 0; r < quad_rows; ++r) {
    for (int c = 0; c < g_.cols; ++c) column_sparse[std::size_t(c)] = spacing(r, c) > max_spacing_m;
    for (int c = 0; c < quad_cols; ++c)
      sparse_[std::size_t(r) * quad_cols + c] =
          column_sparse[std::size_t(c)] || column_sparse[std::size_t(c) + 1];
  }
}

// Where each border scanline meets the ground, column by column: the
// border pixel's horizontal reach where it and the pixel two scanlines in
// are ground (returns, in quads that are neither occluding edges nor steep
// faces), less two standard deviations of its range noise; a column without
// ground takes that of the nearest column with ground on the same surface.
// The border splits into surfaces where neighbouring columns are across
// an occluding edge. A surface nearer than the surfaces on both its sides
// (on the one side at the image's edge) is an obstacle standing up into
// the last scanline, its top say: what it hides lies before the ground
// beside it, whose reach it takes, interpolated across it from one side
// to the other.
void LocusTables::findBorderGround(const OccludingEdges& edges) {
  for (int b = 0; b < 2; ++b) {
    for (auto* v : {&border_reach_[std::size_t(b)], &border_own_from_[std::size_t(b)],
                    &border_own_to_[std::size_t(b)]})
      v->assign(std::size_t(g_.cols), NAN);
    if (g_.rows < 3 || g_.cols < 2) continue;
    const int border = b == 0 ? 0 : g_.rows - 1;
    findOwnBorderGround(b, edges);
    const auto surfaces = borderSurfaces(border, edges);
    fillFromNearestGround(border_reach_[std::size_t(b)], surfaces);
    reachAcrossObstacles(border, surfaces, border_reach_[std::size_t(b)]);
  }
}

// Each border column whose pixel and the pixel two scanlines in are ground
// (returns, in quads that are neither occluding edges nor steep faces).
void LocusTables::findOwnBorderGround(int b, const OccludingEdges& edges) {
  const int cols = g_.cols;
  const double k = image_.range_sigma_k;
  auto& reach = border_reach_[std::size_t(b)];
  auto& own_from = border_own_from_[std::size_t(b)];
  auto& own_to = border_own_to_[std::size_t(b)];
  const int border = b == 0 ? 0 : g_.rows - 1, in = b == 0 ? 2 : g_.rows - 3;
  for (int c = 0; c < cols; ++c) {
    const int qc = std::min(c, cols - 2);
    bool ground = true;
    for (int r = std::min(border, in); r <= std::max(border, in); ++r)
      ground = ground && hasReturn(r, qc) && hasReturn(r, qc + 1);
    for (int qr = std::min(border, in); ground && qr < std::max(border, in); ++qr)
      ground = !edges.quadIsEdge(qr, qc) && !isSteepFace(qr, qc);
    if (!ground) continue;
    const double rho = image_.at(border, c);
    const double noise = 2 * k * rho * rho;
    const double across = reachAt(border, c);
    reach[std::size_t(c)] = own_from[std::size_t(c)] = across - noise;
    const double step = across - reachAt(border == 0 ? 1 : border - 1, c);
    own_to[std::size_t(c)] = across + std::max(step, 0.0) + noise;
  }
}

// The border scanline's surfaces: runs of columns with continuous ranges.
std::vector<LocusTables::BorderSurface> LocusTables::borderSurfaces(
    int border, const OccludingEdges& edges) const {
  auto continuous = [&](int c) {  // columns c and c + 1
    return hasReturn(border, c) && hasReturn(border, c + 1) && !edges.rightPairIsEdge(border, c);
  };
  std::vector<BorderSurface> surfaces;
  for (int c = 0; c < g_.cols; ++c)
    if (c == 0 || !continuous(c - 1))
      surfaces.push_back({c, c});
    else
      surfaces.back().last = c;
  return surfaces;
}

// Within a surface, columns without ground take the nearest ground's reach
// (the left one on a tie): the nearest ground column to the left, then to
// the right, each found in one pass.
void LocusTables::fillFromNearestGround(std::vector<double>& reach,
                                        const std::vector<BorderSurface>& surfaces) {
  const auto ground = reach;
  const auto hasGround = [&](int c) { return !std::isnan(ground[std::size_t(c)]); };
  std::vector<int> left(reach.size(), -1);
  for (const auto& f : surfaces)
    for (int c = f.first, last = -1; c <= f.last; ++c)
      left[std::size_t(c)] = last = hasGround(c) ? c : last;
  for (const auto& f : surfaces)
    for (int c = f.last, right = -1; c >= f.first; --c) {
      right = hasGround(c) ? c : right;
      const int l = left[std::size_t(c)];
      const int nearest = l >= 0 && (right < 0 || c - l <= right - c) ? l : right;
      if (nearest >= 0) reach[std::size_t(c)] = ground[std::size_t(nearest)];
    }
}

// A surface nearer than the surfaces on both its sides (on the one side at
// the image's edge) stands up into the border scanline: it takes the reach
// of the ground beside it, interpolated across it from one side to the other.
void LocusTables::reachAcrossObstacles(int border, const std::vector<BorderSurface>& surfaces,
                                       std::vector<double>& reach) const {
  const auto own = reach;
  auto nearerThan = [&](int c, int beside) {  // column c's range below its neighbour's
    return hasReturn(border, c) &&
           (!hasReturn(border, beside) || image_.at(border, c) < image_.at(border, beside));
  };
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const auto& f = surfaces[i];
    const bool left = i > 0, right = i + 1 < surfaces.size();
    if (!left && !right) continue;
    if ((left && !nearerThan(f.first, f.first - 1)) || (right && !nearerThan(f.last, f.last + 1)))
      continue;
    const double a = left ? own[std::size_t(f.first - 1)] : NAN;
    const double z = right ? own[std::size_t(f.last + 1)] : NAN;
    for (int c = f.first; c <= f.last; ++c) {
      const double w = double(c - f.first + 1) / (f.last - f.first + 2);
      reach[std::size_t(c)] = std::isnan(a) ? z : std::isnan(z) ? a : a + w * (z - a);
    }
  }
}

}  // namespace ambler::terrain
