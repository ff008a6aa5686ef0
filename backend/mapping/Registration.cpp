#include "mapping/Registration.h"

#include <omp.h>
#include <tsl/robin_map.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/SideBySide.h"
#include "mapping/HeightSearch.h"
#include "mapping/PointIndex.h"

namespace ambler::mapping {

void validate(const RegistrationOptions& o) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("registration option " + what);
  };
  require(o.ray_voxel_m > 0 && o.ray_voxel_m <= o.voxel_m, "ray_voxel_m must be in (0, voxel_m]");
  require(o.ray_neighbours == 0 || (o.ray_neighbours >= 5 && o.ray_neighbours <= 100),
          "ray_neighbours must be 0 or in [5, 100]");
  require(o.voxel_m > 0 && o.voxel_m <= 1e3, "voxel_m must be in (0, 1 km]");
  require(o.source_voxel_m >= o.voxel_m && o.source_voxel_m <= 1e3,
          "source_voxel_m must be in [voxel_m, 1 km]");
  require(o.neighbours >= 5 && o.neighbours <= 100, "neighbours must be in [5, 100]");
  require(o.min_thickness_m > 0, "min_thickness_m must be positive");
  require(o.min_distance_m > 0 && o.max_distance_m >= o.min_distance_m,
          "max_distance_m must be >= min_distance_m > 0");
  require(o.kernel_sigmas > 0, "kernel_sigmas must be positive");
  require(o.max_iterations >= 1 && o.max_iterations <= 10000,
          "max_iterations must be in [1, 10000]");
  require(o.min_step >= 0, "min_step must be >= 0");
  require(o.threads >= 0 && o.threads <= 1024, "threads must be in [0, 1024]");
  require(o.partner_distance_m > 0 && o.partner_plane_m > 0,
          "partner_distance_m and partner_plane_m must be positive");
  require(o.min_overlap >= 0 && o.min_overlap <= o.trusted_overlap && o.trusted_overlap <= 1,
          "overlaps must satisfy 0 <= min_overlap <= trusted_overlap <= 1");
  require(o.max_rms_m > 0, "max_rms_m must be positive");
  require(o.max_residual_ratio == 0 || o.max_residual_ratio >= 1,
          "max_residual_ratio must be 0 (off) or at least 1");
  require(o.sigma_floor_m > 0, "sigma_floor_m must be positive");
  require(o.agreement_tolerance_m > 0, "agreement_tolerance_m must be positive");
  require(o.abandon_agreement >= 0 && o.abandon_agreement <= o.min_agreement,
          "abandon_agreement must be in [0, min_agreement]");
  require(o.min_agreement >= 0 && o.min_agreement <= 1, "min_agreement must be in [0, 1]");
  require(o.doubtful_sigma_m > 0 && o.degenerate_sigma_m >= o.doubtful_sigma_m,
          "sigmas must satisfy 0 < doubtful_sigma_m <= degenerate_sigma_m");
}

Cloud transformed(const Cloud& cloud, const Eigen::Isometry3d& motion) {
  Cloud out;
  out.reserve(cloud.size());
  for (const auto& p : cloud) out.push_back(motion * p);
  return out;
}

const char* verdictName(Verdict verdict) {
  switch (verdict) {
    case Verdict::kTrusted:
      return "trusted";
    case Verdict::kDoubtful:
      return "doubtful";
    case Verdict::kDegenerate:
      return "degenerate";
    case Verdict::kNoOverlap:
      return "no overlap";
  }
  return "no overlap";
}

namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

// A thinned point with the shape of its neighbourhood.
struct Surfel {
  Eigen::Vector3d p;
  Eigen::Matrix3d cov;
  Eigen::Vector3d normal;
  double along = 0;  // cov's variance along the surface (across: min_thickness_m squared)
};

// The cloud's centroid and principal axes, signed by the third moment
// along each: a frame that moves with the cloud.
Eigen::Isometry3d principalFrame(const Cloud& cloud) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : cloud) c += p;
  c /= double(cloud.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : cloud) cov += (p - c) * (p - c).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  Eigen::Vector3d e1 = es.eigenvectors().col(2), e2 = es.eigenvectors().col(1);
  double m1 = 0, m2 = 0;
  for (const auto& p : cloud) {
    const double u = (p - c).dot(e1), v = (p - c).dot(e2);
    m1 += u * u * u, m2 += v * v * v;  // only the signs count: no std::pow library call
  }
  if (m1 < 0) e1 = -e1;
  if (m2 < 0) e2 = -e2;
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  frame.linear().col(0) = e1;
  frame.linear().col(1) = e2;
  frame.linear().col(2) = e1.cross(e2);
  frame.translation() = c;
  return frame;
}

// A cell's index packed in 21 bits per axis, for cells within kVoxelSpan
// of the origin.
constexpr std::int64_t kVoxelSpan = std::int64_t(1) << 20;
std::uint64_t cellKey(const Eigen::Vector3i& c) {
  std::uint64_t key = 0;
  for (int a = 0; a < 3; ++a) key = key << 21 | std::uint64_t(std::int64_t(c[a]) + kVoxelSpan);
  return key;
}
Eigen::Vector3i cellOfPoint(const Eigen::Vector3d& p, double cell) {
  return (p / cell).array().floor().cast<int>();
}
std::uint64_t voxelKey(const Eigen::Vector3d& p, double voxel) {
  return cellKey(cellOfPoint(p, voxel));
}
// The keys' low bits are one axis alone: mixed (MurmurHash3's finalizer)
// before the open-addressed map takes them modulo its power-of-two size.
struct KeyHash {
  std::size_t operator()(std::uint64_t k) const {
    k ^= k >> 33, k *= 0xff51afd7ed558ccdULL, k ^= k >> 33;
    return std::size_t(k);
  }
};
template <class Value>
using CellMap = tsl::robin_map<std::uint64_t, Value, KeyHash>;

// One mean point per occupied voxel, in the order the voxels were first met.
std::vector<Eigen::Vector3d> voxelMeans(const Cloud& cloud, const Eigen::Isometry3d& to_frame,
                                        double voxel) {
  CellMap<std::size_t> slot;
  std::vector<Eigen::Vector3d> sum;
  std::vector<int> count;
  // A scan's points come row by row, often several to a voxel: the last
  // voxel is looked at before the map, whose lookups miss the cache.
  std::uint64_t last_key = 0;
  std::size_t last = std::size_t(-1);
  for (const auto& raw : cloud) {
    const Eigen::Vector3d p = to_frame * raw;
    const Eigen::Vector3d in_voxels = p / voxel;
    if ((in_voxels.array().abs() >= double(kVoxelSpan - 1)).any())
      throw std::invalid_argument("registration: a point lies over " +
                                  std::to_string(int(kVoxelSpan * voxel / 1000)) +
                                  " km from the target's centre");
    const std::uint64_t key = cellKey(in_voxels.array().floor().cast<int>());
    if (last == std::size_t(-1) || key != last_key) {
      const auto [it, fresh] = slot.try_emplace(key, sum.size());
      if (fresh) sum.emplace_back(Eigen::Vector3d::Zero()), count.push_back(0);
      last_key = key, last = it->second;
    }
    sum[last] += p, ++count[last];
  }
  for (std::size_t i = 0; i < sum.size(); ++i) sum[i] /= count[i];
  return sum;
}

std::vector<Eigen::Vector3f> asFloat(const std::vector<Eigen::Vector3d>& points) {
  std::vector<Eigen::Vector3f> out;
  out.reserve(points.size());
  for (const auto& p : points) out.push_back(p.cast<float>());
  return out;
}

// Sums over points, from which their mean and covariance follow.
struct Moments {
  double n = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  void add(const Eigen::Vector3d& p) { n += 1, sum += p, outer.noalias() += p * p.transpose(); }
  void add(const Moments& m) { n += m.n, sum += m.sum, outer += m.outer; }
};

// The points' moments in cubic cells of one size, and for each occupied
// cell those of the 3 x 3 x 3 cells around it.
class CellBlocks {
 public:
  CellBlocks(const std::vector<Eigen::Vector3d>& points, double cell, int threads) : cell_(cell) {
    index_.reserve(points.size());
    holding_.reserve(points.size());
    for (const auto& p : points) {
      holding_.push_back(cellOf(cellOfPoint(p, cell_)));
      cells_[holding_.back()].add(p);
    }
    sumBlocks(threads);
  }
  // Cells twice the size of `finer`'s, from its cells.
  CellBlocks(const CellBlocks& finer, int threads) : cell_(2 * finer.cell_) {
    index_.reserve(finer.size());
    for (std::size_t c = 0; c < finer.cells_.size(); ++c)
      cells_[cellOf(finer.coords_[c].unaryExpr([](int v) { return v >> 1; }))].add(finer.cells_[c]);
    sumBlocks(threads);
  }
  std::size_t size() const { return cells_.size(); }
  const Eigen::Vector3i& cell(std::size_t c) const { return coords_[c]; }
  // The cell holding point `i` of those given (built from points, not cells).
  std::size_t holding(std::size_t i) const { return holding_[i]; }
  // The block around cell `c`, one of the occupied ones.
  const Moments& around(const Eigen::Vector3i& c) const { return blocks_[index_.at(cellKey(c))]; }
  const Moments& around(std::size_t c) const { return blocks_[c]; }

 private:
  // The index of cell `c`, added if new. Points and finer cells come in
  // scan order, often several to a cell: the last cell is looked at before
  // the map (as in voxelMeans).
  std::size_t cellOf(const Eigen::Vector3i& c) {
    const std::uint64_t key = cellKey(c);
    if (cells_.empty() || key != last_key_) {
      const auto [it, fresh] = index_.try_emplace(key, cells_.size());
      if (fresh) cells_.emplace_back(), coords_.push_back(c);
      last_key_ = key, last_ = it->second;
    }
    return last_;
  }
  void sumBlocks(int threads) {
    blocks_.resize(cells_.size());
#pragma omp parallel for schedule(static) num_threads(threads)
    for (std::size_t c = 0; c < cells_.size(); ++c)
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            const auto it = index_.find(cellKey(coords_[c] + Eigen::Vector3i(dx, dy, dz)));
            if (it != index_.end()) blocks_[c].add(cells_[it->second]);
          }
  }
  double cell_;
  std::uint64_t last_key_ = 0;
  std::size_t last_ = 0;  // the cell of last_key_
  CellMap<std::size_t> index_;
  std::vector<Eigen::Vector3i> coords_;
  std::vector<Moments> cells_, blocks_;
  std::vector<std::size_t> holding_;  // of each point given, its cell
};

// The mean and principal axes of some points (eigenvalues ascending: the
// first eigenvector is the normal).
struct Plane {
  Eigen::Vector3d mean;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> shape;
};

// Of a point's k nearest neighbours.
Plane nearestPlane(const std::vector<Eigen::Vector3d>& points, const PointIndex& index,
                   const Eigen::Vector3d& at, int k) {
  std::array<unsigned, 100> idx{};
  std::array<float, 100> d2{};
  const int n = index.nearest(at.cast<float>(), k, idx.data(), d2.data());
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int j = 0; j < n; ++j) mean += points[idx[std::size_t(j)]];
  mean /= n;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int j = 0; j < n; ++j) {
    const Eigen::Vector3d d = points[idx[std::size_t(j)]] - mean;
    cov += d * d.transpose();
  }
  return {mean, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov / n)};
}

// Cells from `first_cell`, doubling up to 4 m (KISS-ICP's
// voxel hashing, with moments instead of points): a point's neighbourhood
// is a block of cells around its own, found in constant time.
std::vector<CellBlocks> cellScales(const std::vector<Eigen::Vector3d>& points, double first_cell,
                                   int threads) {
  std::vector<CellBlocks> scales;
  scales.emplace_back(points, first_cell, threads);
  for (double cell = 2 * first_cell; cell <= 4.0; cell *= 2)
    scales.emplace_back(scales.back(), threads);
  return scales;
}

// For each cell of the finest scale, the plane of the smallest block
// around it holding at least k points (none when no block does). A finer
// cell lies in one cell of each coarser scale, found by halving its
// coordinates (arithmetic shifts floor negatives too).
std::vector<std::optional<Plane>> cellPlanes(const std::vector<CellBlocks>& scales, int k,
                                             int threads) {
  std::vector<std::optional<Plane>> planes(scales.front().size());
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t c = 0; c < planes.size(); ++c) {
    for (std::size_t j = 0; j < scales.size(); ++j) {
      const Moments& block =
          j == 0 ? scales[0].around(c)
                 : scales[j].around(scales[0].cell(c).unaryExpr([&](int v) { return v >> j; }));
      if (block.n < k) continue;
      Plane plane{block.sum / block.n, {}};
      plane.shape.computeDirect(block.outer / block.n - plane.mean * plane.mean.transpose());
      planes[c] = plane;
      break;
    }
  }
  return planes;
}

// Each point moved along its ray from `scanner` onto the plane of the
// points around it (cellPlanes), by at most three times their spread
// across it: a range error lies along the ray. The block grows with range
// as the points thin out, and the noise grows. Rays within 6 degrees of
// grazing the plane stay (the crossing is ill-defined there).
std::vector<Eigen::Vector3d> ontoNeighbourPlanes(const std::vector<Eigen::Vector3d>& points,
                                                 const Eigen::Vector3d& scanner, double spacing,
                                                 int k, int threads) {
  // The first cells are four spacings wide: blocks of cells two spacings
  // wide hold about 36 points of a plane, too few to be chosen.
  const auto scales = cellScales(points, 4 * spacing, threads);
  const auto planes = cellPlanes(scales, k, threads);
  std::vector<Eigen::Vector3d> out(points);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& plane = planes[scales.front().holding(i)];
    if (!plane) continue;
    const Eigen::Vector3d normal = plane->shape.eigenvectors().col(0);
    const Eigen::Vector3d ray = (points[i] - scanner).normalized();
    const double cosine = normal.dot(ray);
    if (!(std::abs(cosine) >= 0.1)) continue;
    const double reach =
        3 * std::sqrt(std::max(plane->shape.eigenvalues()[0], 0.0)) / std::abs(cosine);
    out[i] += std::clamp(-normal.dot(points[i] - plane->mean) / cosine, -reach, reach) * ray;
  }
  return out;
}

// Each point's neighbourhood (the smallest block of cells around it holding
// `neighbours` points, else as many nearest points) as a covariance: a
// plane along its normal, as thin across as the floor and as wide along as
// the neighbourhood's narrower spread (at least a voxel), so that pairs
// pull across surfaces and slide along them (plane-to-plane GICP). Not the
// neighbourhood's measured thickness: on noisy scans that is noise, and
// the fit follows it.
std::vector<Surfel> surfels(const std::vector<Eigen::Vector3d>& points,
                            const RegistrationOptions& o, int threads) {
  const int k = o.neighbours;
  const auto scales = cellScales(points, 2 * o.voxel_m, threads);
  const auto planes = cellPlanes(scales, k, threads);
  // Points too sparse for any block take their k nearest neighbours.
  std::unique_ptr<PointIndex> index;
  if (std::any_of(planes.begin(), planes.end(), [](const auto& p) { return !p; }))
    index = std::make_unique<PointIndex>(asFloat(points));
  std::vector<Surfel> out(points.size());
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& block = planes[scales.front().holding(i)];
    const auto& es = block ? block->shape : nearestPlane(points, *index, points[i], k).shape;
    const Eigen::Vector3d normal = es.eigenvectors().col(0);
    const Eigen::Matrix3d across = normal * normal.transpose();
    const double along = std::max(es.eigenvalues()[1], o.voxel_m * o.voxel_m);
    out[i] = {points[i],
              o.min_thickness_m * o.min_thickness_m * across +
                  along * (Eigen::Matrix3d::Identity() - across),
              normal, along};
  }
  return out;
}

const Eigen::Vector3d& position(const Surfel& s) { return s.p; }
const Eigen::Vector3d& position(const Eigen::Vector3d& p) { return p; }

// One per coarse voxel, the first met.
template <class Point>
std::vector<Point> sparser(const std::vector<Point>& points, double voxel) {
  CellMap<char> seen;
  std::vector<Point> out;
  for (const auto& p : points) {
    if (seen.try_emplace(voxelKey(position(p), voxel), 1).second) out.push_back(p);
  }
  return out;
}

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Eigen::Isometry3d exp(const Vector6d& step) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d w = step.head<3>();
  if (w.norm() > 0) t.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  t.translation() = step.tail<3>();
  return t;
}

// Normal equations summed in fixed chunks, then the chunks in order: the
// same sums whatever the number of threads.
struct NormalEquations {
  Matrix6d h = Matrix6d::Zero();
  Vector6d g = Vector6d::Zero();
  std::size_t pairs = 0;
  double cost = 0;                    // kernel cost, unpaired points saturated (GICP)
  double residual2 = 0, radius2 = 0;  // sums over the pairs, for the verdict
  void add(const NormalEquations& o) {
    h += o.h, g += o.g, pairs += o.pairs, cost += o.cost, residual2 += o.residual2,
        radius2 += o.radius2;
  }
};

constexpr int kChunks = 64;

template <class PerPoint>
NormalEquations accumulate(std::size_t n, int threads, PerPoint&& per_point) {
  std::array<NormalEquations, kChunks> chunks;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (int c = 0; c < kChunks; ++c)
    for (std::size_t i = n * std::size_t(c) / kChunks; i < n * std::size_t(c + 1) / kChunks; ++i)
      per_point(i, chunks[std::size_t(c)]);
  NormalEquations total;
  for (const auto& c : chunks) total.add(c);
  return total;
}

struct Fit {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  bool converged = false;
  int iterations = 0;
  std::size_t pairs = 0;
  double cost = INFINITY;  // mean kernel cost per source point, unpaired ones saturated
};

// Each source point's nearest target point, kept from one iteration to the
// next while the point has moved less than half its lead over the next
// nearest (no other target point can have come nearer): once the steps are
// small most points skip the k-d tree, and their partners are those a
// search would give.
class Partners {
 public:
  Partners(const PointIndex& index, std::size_t n) : index_(index), found_(n) {}
  int of(std::size_t i, const Eigen::Vector3f& at, float limit2) {
    Found& f = found_[i];
    if (f.index >= 0 && 2 * (at - f.at).norm() + kMargin < f.lead &&
        (index_.points()[std::size_t(f.index)] - at).squaredNorm() < limit2 * (1 - 1e-5f))
      return f.index;
    f.index = index_.nearestWithLead(at, limit2, f.lead).index;
    f.at = at;
    return f.index;
  }

 private:
  // Well above the rounding of single-precision distances over a scan.
  static constexpr float kMargin = 1e-4f;  // [m]
  struct Found {
    int index = -1;
    Eigen::Vector3f at = Eigen::Vector3f::Zero();
    float lead = 0.0f;
  };
  const PointIndex& index_;
  std::vector<Found> found_;
};

// The source surfel's covariance turned by r, plus the target's. The
// source's is along * I + (across2 - along) n n^T: only its normal turns.
Eigen::Matrix3d pairCovariance(const Surfel& source, const Surfel& target, const Eigen::Matrix3d& r,
                               double across2) {
  const Eigen::Vector3d n = r * source.normal;
  Eigen::Matrix3d sum = target.cov;
  sum.noalias() += (across2 - source.along) * n * n.transpose();
  sum.diagonal().array() += source.along;
  return sum;
}

// A pair's share of the normal equations of the step (turn, shift), with
// weight matrix m and residual e at the moved source point q. The
// Jacobian is J = [skew(q), -I], so J^T m J and J^T m e go by blocks
// (skew(q)^T = -skew(q)).
void addPair(NormalEquations& sum, const Eigen::Vector3d& q, const Eigen::Vector3d& e,
             const Eigen::Matrix3d& m) {
  const Eigen::Matrix3d a = skew(q), ma = m * a;
  const Eigen::Vector3d me = m * e;
  sum.h.topLeftCorner<3, 3>().noalias() -= a * ma;
  sum.h.topRightCorner<3, 3>() -= ma.transpose();
  sum.h.bottomLeftCorner<3, 3>() -= ma;
  sum.h.bottomRightCorner<3, 3>() += m;
  sum.g.head<3>().noalias() -= a * me;
  sum.g.tail<3>() -= me;
  ++sum.pairs;
}

Fit gicp(const std::vector<Surfel>& source, const std::vector<Surfel>& target,
         const PointIndex& index, const Eigen::Isometry3d& start, const RegistrationOptions& o,
         int threads) {
  Fit fit;
  fit.transform = start;
  double distance = o.max_distance_m;
  int in_stage = 0;
  const double c2 = o.kernel_sigmas * o.kernel_sigmas;
  const double across2 = o.min_thickness_m * o.min_thickness_m;
  Partners partners(index, source.size());
  while (fit.iterations < o.max_iterations) {
    ++fit.iterations;
    const Eigen::Matrix3d r = fit.transform.linear();
    const float limit2 = float(distance * distance);
    const auto eq = accumulate(source.size(), threads, [&](std::size_t i, NormalEquations& sum) {
      const Eigen::Vector3d q = fit.transform * source[i].p;
      const int partner = partners.of(i, q.cast<float>(), limit2);
      if (partner < 0) {
        sum.cost += c2;
        return;
      }
      const Surfel& t = target[std::size_t(partner)];
      const Eigen::Vector3d e = t.p - q;
      const Eigen::Matrix3d info = pairCovariance(source[i], t, r, across2).inverse();
      const double m2 = e.dot(info * e);
      sum.cost += c2 * m2 / (c2 + m2);
      const double w = 1.0 / ((1.0 + m2 / c2) * (1.0 + m2 / c2));
      addPair(sum, q, e, w * info);
    });
    fit.pairs = eq.pairs;
    fit.cost = eq.cost / double(std::max<std::size_t>(source.size(), 1));
    if (eq.pairs < 6) return fit;
    const double damping = 1e-9 * eq.h.trace();
    const Vector6d step = -(eq.h + damping * Matrix6d::Identity()).ldlt().solve(eq.g);
    if (!step.allFinite()) return fit;
    fit.transform = exp(step) * fit.transform;
    // A stage ends when its steps move points by a small share of its
    // pairing distance, or after a third of the iterations; the last one
    // when they are negligible.
    const bool last = distance <= o.min_distance_m;
    const double tolerance = last ? o.min_step : 1e-3 * distance;
    ++in_stage;
    if (step.head<3>().norm() * 10 < tolerance && step.tail<3>().norm() < tolerance) {
      if (last) {
        fit.converged = true;
        return fit;
      }
    } else if (last || in_stage < o.max_iterations / 3) {
      continue;
    }
    distance = std::max(o.min_distance_m, distance / 2);
    in_stage = 0;
  }
  return fit;
}

std::string axisName(const Eigen::Vector3d& v, const char* const names[3]) {
  for (int a = 0; a < 3; ++a)
    if (std::abs(v[a]) >= 0.9 * v.norm()) return names[a];
  char text[96];
  std::snprintf(text, sizeof text, "(%.2f, %.2f, %.2f)", v.x(), v.y(), v.z());
  return std::string(names[3]) + " " + text;
}

// Point-to-plane residuals of `points`, moved by `motion`, each against the
// nearest surfel within the partner limits, with the normal equations of
// their conditioning.
NormalEquations planeResiduals(const std::vector<Eigen::Vector3d>& points,
                               const Eigen::Isometry3d& motion, const std::vector<Surfel>& surfels,
                               const PointIndex& index, const RegistrationOptions& o, int threads) {
  const float limit2 = float(o.partner_distance_m * o.partner_distance_m);
  return accumulate(points.size(), threads, [&](std::size_t i, NormalEquations& sum) {
    const Eigen::Vector3d p = motion * points[i];
    const auto hit = index.nearest(p.cast<float>(), limit2);
    if (hit.index < 0) return;
    const Surfel& t = surfels[std::size_t(hit.index)];
    const double d = t.normal.dot(p - t.p);
    if (std::abs(d) > o.partner_plane_m) return;
    Vector6d j;
    j << p.cross(t.normal), t.normal;
    sum.h += j * j.transpose();
    sum.residual2 += d * d;
    sum.radius2 += p.squaredNorm();
    ++sum.pairs;
  });
}

double rms(const NormalEquations& eq) {
  return eq.pairs ? std::sqrt(eq.residual2 / double(eq.pairs)) : 0.0;
}

std::string formatted(const char* format, auto... values) {
  char text[200];
  std::snprintf(text, sizeof text, format, values...);
  return text;
}

// Why the source shares too little with the target to be of the same
// ground (partners, height agreement), or nothing.
std::optional<std::string> sharesTooLittle(const RegistrationQuality& q, std::size_t pairs,
                                           const RegistrationOptions& o) {
  if (pairs < 30 || q.overlap < o.min_overlap)
    return formatted(
        "%.0f %% of the source's points have a partner in the target; at least %.0f %% needed",
        100 * q.overlap, 100 * o.min_overlap);
  if (o.min_agreement > 0 && !(q.agreement >= o.min_agreement))
    return formatted(
        "the clouds' heights agree within %.0f mm on %.0f %% of the ground they share; at least "
        "%.0f %% for the same ground",
        1000 * o.agreement_tolerance_m, 100 * q.agreement, 100 * o.min_agreement);
  return std::nullopt;
}

// Ground the source shares with the target fits the target's surface
// about as well as the source's own; another place's gentle ground can
// agree in height within the tolerance and still not.
std::optional<std::string> fitsAnotherSurface(const RegistrationQuality& q,
                                              const RegistrationOptions& o) {
  const double own = std::max(q.self_rms_m, o.sigma_floor_m);
  if (o.max_residual_ratio > 0 && q.rms_m > o.max_residual_ratio * own)
    return formatted(
        "the source lies %.1f mm off the target's surface and %.1f mm off its own; at most %.1f "
        "times %.1f mm for the same ground",
        1000 * q.rms_m, 1000 * q.self_rms_m, o.max_residual_ratio, 1000 * own);
  return std::nullopt;
}

// The conditioning of the point-to-plane problem over the partners: its
// weakest direction and the standard deviation per axis; `frame` turns
// the working frame's directions into the target's.
void weighConditioning(RegistrationQuality& q, const NormalEquations& eq,
                       const Eigen::Isometry3d& frame, const RegistrationOptions& o) {
  const double radius = std::max(std::sqrt(eq.radius2 / double(eq.pairs)), 1e-3);
  // Rotations scaled to the motion of a point at the clouds' radius.
  Vector6d scale;
  scale << Eigen::Vector3d::Constant(1 / radius), Eigen::Vector3d::Ones();
  const Matrix6d h = scale.asDiagonal() * eq.h * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Matrix6d> es(h);
  const double noise = std::max(q.rms_m, o.sigma_floor_m);
  const double weakest = es.eigenvalues()[0];
  q.weakest_sigma_m = weakest > 0 ? noise / std::sqrt(weakest) : INFINITY;
  const Vector6d u = es.eigenvectors().col(0);
  q.weakest_rotation = frame.linear() * u.head<3>();
  q.weakest_translation = frame.linear() * u.tail<3>();
  static const char* const kTranslations[] = {"x", "y", "z", "translation"};
  static const char* const kRotations[] = {"roll", "pitch", "yaw", "rotation"};
  q.weakest_axis = q.weakest_translation.squaredNorm() >= 0.5
                       ? axisName(q.weakest_translation, kTranslations)
                       : axisName(q.weakest_rotation, kRotations);
  if (weakest > 0 && es.eigenvalues()[0] / es.eigenvalues()[5] > 1e-12) {
    const Matrix6d cov = noise * noise * h.inverse();
    Eigen::Matrix3d rot = cov.topLeftCorner<3, 3>() / (radius * radius);
    Eigen::Matrix3d trans = cov.bottomRightCorner<3, 3>();
    rot = frame.linear() * rot * frame.linear().transpose();
    trans = frame.linear() * trans * frame.linear().transpose();
    q.sigma << trans.diagonal().cwiseSqrt(), rot.diagonal().cwiseSqrt();
  } else {
    q.sigma.setConstant(INFINITY);
  }
}

// Degenerate, doubtful or trusted, with the reason, for clouds of the same
// ground.
void pronounce(RegistrationQuality& q, const Fit& fit, const RegistrationOptions& o) {
  if (q.weakest_sigma_m > o.degenerate_sigma_m) {
    q.verdict = Verdict::kDegenerate;
    q.reason = formatted("the ground does not hold the fit along %s (+-%.1f mm)",
                         q.weakest_axis.c_str(), 1000 * std::min(q.weakest_sigma_m, 1e9));
  } else if (!fit.converged) {
    q.verdict = Verdict::kDoubtful;
    q.reason = formatted("did not settle in %d iterations", fit.iterations);
  } else if (q.overlap < o.trusted_overlap) {
    q.verdict = Verdict::kDoubtful;
    q.reason = formatted("only %.0f %% of the source's points have a partner", 100 * q.overlap);
  } else if (q.rms_m > o.max_rms_m) {
    q.verdict = Verdict::kDoubtful;
    q.reason = formatted("residual %.1f mm over the partners, above %.0f mm", 1000 * q.rms_m,
                         1000 * o.max_rms_m);
    // Beside the source's residual on its own surface: at about that level
    // the residual is the scan's range noise, not a misfit.
    if (q.self_rms_m > 0)
      q.reason += formatted(" (the source on its own surface: %.1f mm)", 1000 * q.self_rms_m);
  } else if (q.weakest_sigma_m > o.doubtful_sigma_m) {
    q.verdict = Verdict::kDoubtful;
    q.reason = formatted("loosely held along %s (+-%.1f mm)", q.weakest_axis.c_str(),
                         1000 * q.weakest_sigma_m);
  } else {
    q.verdict = Verdict::kTrusted;
    q.reason.clear();
  }
}

// Partners, residual and the conditioning of the point-to-plane problem at
// the fit, and the verdict; `self_rms` is the source's residual against its
// own surface.
RegistrationQuality judge(const std::vector<Eigen::Vector3d>& source,
                          const std::vector<Surfel>& target, const PointIndex& index,
                          const Fit& fit, const Eigen::Isometry3d& frame, double agreement,
                          double self_rms, const RegistrationOptions& o, int threads) {
  RegistrationQuality q;
  q.agreement = agreement;
  q.self_rms_m = self_rms;
  const auto eq = planeResiduals(source, fit.transform, target, index, o, threads);
  q.partners = int(eq.pairs);
  q.overlap = source.empty() ? 0.0 : double(eq.pairs) / double(source.size());
  auto refused = [&q](std::string why) {
    q.verdict = Verdict::kNoOverlap;
    q.reason = std::move(why);
    return q;
  };
  if (auto why = sharesTooLittle(q, eq.pairs, o)) return refused(*why);
  q.rms_m = rms(eq);
  if (auto why = fitsAnotherSurface(q, o)) return refused(*why);
  weighConditioning(q, eq, frame, o);
  pronounce(q, fit, o);
  return q;
}

// The cloud's voxel means in the working frame, its points first moved
// along their rays when its scanner is known; at least 10 of them, so that
// every point has neighbours enough for its covariance.
std::vector<Eigen::Vector3d> thinned(const Cloud& cloud, const Eigen::Isometry3d& to_frame,
                                     const std::optional<Eigen::Vector3d>& scanner,
                                     const RegistrationOptions& o, int threads, const char* which) {
  std::vector<Eigen::Vector3d> out;
  if (scanner && o.ray_neighbours > 0) {
    const auto fine =
        ontoNeighbourPlanes(voxelMeans(cloud, to_frame, o.ray_voxel_m), to_frame * *scanner,
                            o.ray_voxel_m, o.ray_neighbours, threads);
    out = voxelMeans(fine, Eigen::Isometry3d::Identity(), o.voxel_m);
  } else {
    out = voxelMeans(cloud, to_frame, o.voxel_m);
  }
  if (out.size() < 10)
    throw std::invalid_argument(std::string("registration: the ") + which + " has " +
                                std::to_string(out.size()) +
                                " points after thinning; at least 10 needed");
  return out;
}

std::vector<Eigen::Vector3d> positions(const std::vector<Surfel>& surfels,
                                       const Eigen::Isometry3d& motion) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(surfels.size());
  for (const auto& s : surfels) out.push_back(motion * s.p);
  return out;
}

// The target thinned, its k-d tree and its surfels.
struct PreparedTarget {
  std::vector<Eigen::Vector3d> points;
  std::unique_ptr<PointIndex> index;
  std::vector<Surfel> surfels;
};

PreparedTarget prepareTarget(const Cloud& target, const Eigen::Isometry3d& to_frame,
                             const std::optional<Eigen::Vector3d>& scanner,
                             const RegistrationOptions& o, int threads) {
  PreparedTarget t;
  t.points = thinned(target, to_frame, scanner, o, threads, "target");
  t.index = std::make_unique<PointIndex>(asFloat(t.points));
  t.surfels = surfels(t.points, o, threads);
  return t;
}

// The source thinned and its surfels, placed by the guess; and what the
// verdict weighs: its points where the scan put them (moved onto their
// neighbours' planes they share their errors, and their residual would
// understate the noise), one per sparse voxel, and their residual against
// the source's own surface.
struct PreparedSource {
  std::vector<Eigen::Vector3d> points;
  std::vector<Surfel> placed;
  std::vector<Eigen::Vector3d> probe;
  double self_rms = 0.0;
};

PreparedSource prepareSource(const Cloud& source, const Eigen::Isometry3d& to_frame,
                             const std::optional<Eigen::Vector3d>& scanner,
                             const RegistrationOptions& o, int threads) {
  PreparedSource s;
  s.points = thinned(source, to_frame, scanner, o, threads, "source");
  s.placed = surfels(s.points, o, threads);
  const auto as_scanned =
      scanner && o.ray_neighbours > 0 ? voxelMeans(source, to_frame, o.voxel_m) : s.points;
  s.probe = sparser(as_scanned, o.source_voxel_m);
  if (o.max_residual_ratio > 0) {
    const PointIndex own(asFloat(s.points));  // the surfels' centres
    s.self_rms =
        rms(planeResiduals(s.probe, Eigen::Isometry3d::Identity(), s.placed, own, o, threads));
  }
  return s;
}

// Both clouds made ready, side by side when there are cores for it (their
// thinning is mostly hashing, one core's work); the target's error first
// when both are refused, as when made one after the other.
std::pair<PreparedTarget, PreparedSource> prepare(const Cloud& source, const Cloud& target,
                                                  const Eigen::Isometry3d& frame,
                                                  const Eigen::Isometry3d& initial,
                                                  const ScannerOrigins& scanners,
                                                  const RegistrationOptions& o, int threads) {
  auto target_side = [&](int cores) {
    return prepareTarget(target, frame.inverse(), scanners.target, o, cores);
  };
  auto source_side = [&](int cores) {
    return prepareSource(source, frame.inverse() * initial, scanners.source, o, cores);
  };
  if (threads < 2) {
    auto t = target_side(threads);
    return {std::move(t), source_side(threads)};
  }
  return sideBySide([&] { return target_side(threads - threads / 2); },
                    [&] { return source_side(threads / 2); });
}

}  // namespace

Registration registerClouds(const Cloud& source, const Cloud& target,
                            const Eigen::Isometry3d& initial, const RegistrationOptions& o,
                            const ScannerOrigins& scanners) {
  validate(o);
  if (!initial.matrix().allFinite())
    throw std::invalid_argument("registration: the initial transform is not finite");
  if (source.size() < 10 || target.size() < 10)
    throw std::invalid_argument("registration: a cloud has fewer than 10 points");
  for (const auto* cloud : {&source, &target})
    for (const auto& p : *cloud)
      if (!p.allFinite()) throw std::invalid_argument("registration: a point is not finite");
  const int threads = o.threads > 0 ? o.threads : omp_get_max_threads();
  // Everything happens in the target's principal frame: thinning, the
  // height search (its z is across the ground) and GICP.
  const Eigen::Isometry3d frame = principalFrame(target);
  if ((scanners.source && !scanners.source->allFinite()) ||
      (scanners.target && !scanners.target->allFinite()))
    throw std::invalid_argument("registration: a scanner's origin is not finite");
  const auto [prepared_target, prepared_source] =
      prepare(source, target, frame, initial, scanners, o, threads);
  const auto& target_points = prepared_target.points;
  const auto& index = *prepared_target.index;
  const auto& fixed = prepared_target.surfels;
  const auto& source_points = prepared_source.points;
  const auto& placed = prepared_source.placed;
  const auto moving = sparser(placed, o.source_voxel_m);
  Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
  if (o.search_heights) start = searchHeights(source_points, target_points, o.search);
  // Start from the search's placement or from the guess, whichever fits
  // better: on ground that holds a shift only loosely the search can leave
  // a near guess worse off.
  RegistrationOptions coarse = o;
  coarse.max_iterations = 1;
  if (o.search_heights &&
      gicp(moving, fixed, index, Eigen::Isometry3d::Identity(), coarse, threads).cost <
          gicp(moving, fixed, index, start, coarse, threads).cost)
    start = Eigen::Isometry3d::Identity();
  // The sparser source first, then every thinned point from there: fewer
  // points to move while the fit is far, all of them to finish.
  coarse.max_iterations = o.max_iterations;
  coarse.min_step = 3 * o.min_step;
  Fit fit = gicp(moving, fixed, index, start, coarse, threads);
  auto agreementAt = [&](const Eigen::Isometry3d& motion) {
    return o.min_agreement > 0 ? heightAgreement(positions(placed, motion), target_points,
                                                 o.search.cell_m, o.agreement_tolerance_m)
                               : std::numeric_limits<double>::quiet_NaN();
  };
  double agreement = agreementAt(fit.transform);
  if (!(agreement < o.abandon_agreement)) {
    const int first = fit.iterations;
    fit = gicp(placed, fixed, index, fit.transform, o, threads);
    fit.iterations += first;
    agreement = agreementAt(fit.transform);
  }
  Registration r;
  r.transform = frame * fit.transform * frame.inverse() * initial;
  r.converged = fit.converged;
  r.iterations = fit.iterations;
  r.pairs = fit.pairs;
  r.quality = judge(prepared_source.probe, fixed, index, fit, frame, agreement,
                    prepared_source.self_rms, o, threads);
  r.rms_m = r.quality.rms_m;
  return r;
}

}  // namespace ambler::mapping
