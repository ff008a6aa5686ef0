#include "mapping/TerrainMesh.h"

#include <vtkCellArray.h>
#include <vtkDelaunay2D.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <Eigen/Geometry>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

namespace ambler::mapping {

Eigen::Vector3d TerrainMesh::centre(int t) const {
  return (corner(t, 0) + corner(t, 1) + corner(t, 2)) / 3.0;
}

Eigen::Vector3d TerrainMesh::normal(int t) const {
  Eigen::Vector3d n = (corner(t, 1) - corner(t, 0)).cross(corner(t, 2) - corner(t, 0));
  if (n.z() < 0) n = -n;
  return n.normalized();
}

double TerrainMesh::slopeRad(int t) const {
  return std::acos(std::clamp(normal(t).z(), -1.0, 1.0));
}

namespace {

// Twice the signed area of (u, v, w) seen from above: positive when they
// turn counter-clockwise.
double turn(const Eigen::Vector2d& u, const Eigen::Vector2d& v, const Eigen::Vector2d& w) {
  return (v - u).x() * (w - u).y() - (v - u).y() * (w - u).x();
}

}  // namespace

double TerrainMesh::areaXY(int t) const {
  return 0.5 *
         std::abs(turn(corner(t, 0).head<2>(), corner(t, 1).head<2>(), corner(t, 2).head<2>()));
}

Eigen::Vector3d TerrainMesh::pointOn(int t, const Eigen::Vector2d& xy) const {
  const Eigen::Vector3d n = normal(t), a = corner(t, 0);
  return {xy.x(), xy.y(), a.z() - (n.x() * (xy.x() - a.x()) + n.y() * (xy.y() - a.y())) / n.z()};
}

bool TerrainMesh::containsXY(int t, const Eigen::Vector2d& p) const {
  const Eigen::Vector2d a = corner(t, 0).head<2>(), b = corner(t, 1).head<2>(),
                        c = corner(t, 2).head<2>();
  const double d1 = turn(a, b, p), d2 = turn(b, c, p), d3 = turn(c, a, p);
  const double eps = -1e-12 * (1.0 + areaXY(t));
  return (d1 >= eps && d2 >= eps && d3 >= eps) || (d1 <= -eps && d2 <= -eps && d3 <= -eps);
}

void connect(TerrainMesh& mesh) {
  std::map<std::pair<int, int>, std::pair<int, int>> edges;  // (lo, hi) -> (triangle, corner)
  mesh.neighbours.assign(mesh.triangles.size(), {-1, -1, -1});
  for (int t = 0; t < int(mesh.triangles.size()); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles[std::size_t(t)][std::size_t((k + 1) % 3)];
      const int b = mesh.triangles[std::size_t(t)][std::size_t((k + 2) % 3)];
      const auto key = std::minmax(a, b);
      const auto [it, fresh] = edges.try_emplace({key.first, key.second}, t, k);
      if (fresh) continue;
      mesh.neighbours[std::size_t(t)][std::size_t(k)] = it->second.first;
      mesh.neighbours[std::size_t(it->second.first)][std::size_t(it->second.second)] = t;
    }
}

void validate(const MeshOptions& o) {
  if (!(o.tolerance_m > 0 && o.tolerance_m <= 1000))
    throw std::invalid_argument("mesh option tolerance_m must be in (0, 1000] m");
  if (!(o.min_cell_m > 0 && o.min_cell_m <= o.max_cell_m))
    throw std::invalid_argument("mesh option min_cell_m must be in (0, max_cell_m] m");
  if (!(o.max_cell_m <= 1e5))
    throw std::invalid_argument("mesh option max_cell_m must be at most 100 km");
}

namespace {

struct Square {
  Eigen::Vector2d lo;
  double size;
};

// The quadtree's choice of vertices, keyed by position so that corners
// shared by neighbouring squares are one vertex (their heights averaged).
class VertexChooser {
 public:
  VertexChooser(const std::vector<Eigen::Vector3d>& points, const MeshOptions& o,
                const Eigen::Vector2d& lo, const Eigen::Vector2d& hi)
      : points_(points), o_(o), lo_(lo), hi_(hi) {}

  // The occupancy of the root square at min_cell_m: squares with points.
  void start(const Square& root) {
    root_ = root;
    cells_ = std::max(1, int(std::lround(root.size / o_.min_cell_m)));
    occupied_.assign(std::size_t(cells_) * std::size_t(cells_), false);
  }

  void visit(const Square& s, const std::vector<int>& inside) {
    if (inside.empty()) return;
    // A plane through points bunched in one corner (a box's wall, the edge
    // of a shadow) would be extrapolated far to the square's corners: only
    // squares their points span at least halfway across (within the data's
    // bounds) count as flat.
    if (s.size <= o_.max_cell_m * (1 + 1e-6) && inside.size() >= 3 && spans(s, inside)) {
      if (const auto plane = flatFit(inside)) {
        markOccupied(s);
        for (const auto& c : {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 1),
                              Eigen::Vector2d(1, 1)}) {
          // Not beyond the data's bounds: the mesh covers what was seen.
          const Eigen::Vector2d xy = (s.lo + s.size * c).cwiseMax(lo_).cwiseMin(hi_);
          add(xy, plane->dot(Eigen::Vector3d(xy.x(), xy.y(), 1.0)));
        }
        return;
      }
    }
    if (s.size / 2 < o_.min_cell_m) {
      markOccupied(s);
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (int i : inside) mean += points_[std::size_t(i)] / double(inside.size());
      add(mean.head<2>(), mean.z());
      return;
    }
    const double half = s.size / 2;
    std::array<std::vector<int>, 4> parts;
    for (int i : inside) {
      const Eigen::Vector2d d = points_[std::size_t(i)].head<2>() - s.lo;
      parts[std::size_t((d.x() >= half ? 1 : 0) + (d.y() >= half ? 2 : 0))].push_back(i);
    }
    for (int q = 0; q < 4; ++q)
      visit({s.lo + half * Eigen::Vector2d(q % 2, q / 2), half}, parts[std::size_t(q)]);
  }

  std::vector<Eigen::Vector3d> vertices() const {
    std::vector<Eigen::Vector3d> out;
    for (const auto& [key, v] : chosen_) out.push_back({v.x(), v.y(), v.z() / v.w()});
    return out;
  }
  bool overData(const Eigen::Vector2d& xy) const {
    const Eigen::Vector2d f = (xy - root_.lo) / o_.min_cell_m;
    if (!(f.x() >= 0 && f.y() >= 0 && f.x() < cells_ && f.y() < cells_)) return false;
    return occupied_[std::size_t(int(f.y())) * std::size_t(cells_) + std::size_t(int(f.x()))];
  }

 private:
  bool spans(const Square& s, const std::vector<int>& inside) const {
    Eigen::Vector2d lo = points_[std::size_t(inside[0])].head<2>(), hi = lo;
    for (int i : inside)
      lo = lo.cwiseMin(points_[std::size_t(i)].head<2>()),
      hi = hi.cwiseMax(points_[std::size_t(i)].head<2>());
    // Of the square as clipped to the data's bounds.
    const Eigen::Vector2d extent =
        (s.lo + Eigen::Vector2d::Constant(s.size)).cwiseMin(hi_) - s.lo.cwiseMax(lo_);
    return ((hi - lo).array() >= 0.5 * extent.array()).all();
  }

  // z = a x + b y + c through the points, when every one is within tolerance.
  std::optional<Eigen::Vector3d> flatFit(const std::vector<int>& inside) const {
    Eigen::MatrixX3d a(Eigen::Index(inside.size()), 3);
    Eigen::VectorXd z(Eigen::Index(inside.size()));
    for (std::size_t i = 0; i < inside.size(); ++i) {
      const auto& p = points_[std::size_t(inside[i])];
      a.row(Eigen::Index(i)) << p.x(), p.y(), 1.0;
      z(Eigen::Index(i)) = p.z();
    }
    const Eigen::Vector3d plane = a.colPivHouseholderQr().solve(z);
    if (((a * plane) - z).cwiseAbs().maxCoeff() > o_.tolerance_m) return std::nullopt;
    return plane;
  }

  void markOccupied(const Square& s) {
    const Eigen::Vector2d f = (s.lo - root_.lo) / o_.min_cell_m;
    const int c0 = int(std::lround(f.x())), r0 = int(std::lround(f.y()));
    const int n = std::max(1, int(std::lround(s.size / o_.min_cell_m)));
    for (int r = r0; r < std::min(r0 + n, cells_); ++r)
      for (int c = c0; c < std::min(c0 + n, cells_); ++c)
        occupied_[std::size_t(r) * std::size_t(cells_) + std::size_t(c)] = true;
  }

  void add(const Eigen::Vector2d& xy, double z) {
    // Keys on a 1 mm lattice: corners computed from different squares meet.
    const std::pair<long, long> key{std::lround(xy.x() * 1000), std::lround(xy.y() * 1000)};
    auto [it, fresh] = chosen_.try_emplace(key, xy.x(), xy.y(), 0.0, 0.0);
    it->second.z() += z;
    it->second.w() += 1.0;
  }

  const std::vector<Eigen::Vector3d>& points_;
  const MeshOptions& o_;
  Eigen::Vector2d lo_, hi_;                                  // the points' bounds
  std::map<std::pair<long, long>, Eigen::Vector4d> chosen_;  // x, y, sum of z, count
  Square root_{{0, 0}, 1.0};
  int cells_ = 0;
  std::vector<bool> occupied_;  // cells_ x cells_, row-major
};

}  // namespace

TerrainMesh triangulate(const std::vector<Eigen::Vector3d>& points, const MeshOptions& o) {
  validate(o);
  std::vector<Eigen::Vector3d> finite;
  for (const auto& p : points)
    if (p.allFinite()) finite.push_back(p);
  if (finite.size() < 3)
    throw std::invalid_argument("mesh: " + std::to_string(finite.size()) +
                                " finite points, at least 3 needed");
  Eigen::Vector2d lo = finite[0].head<2>(), hi = lo;
  for (const auto& p : finite) lo = lo.cwiseMin(p.head<2>()), hi = hi.cwiseMax(p.head<2>());
  // The root square: the bounds, grown to min_cell_m times a power of two.
  double size = o.min_cell_m;
  while (size < (hi - lo).maxCoeff() + 1e-9) size *= 2;
  std::vector<int> all(finite.size());
  for (std::size_t i = 0; i < finite.size(); ++i) all[i] = int(i);
  VertexChooser chooser(finite, o, lo, hi);
  const Square root{lo, size * (1 + 1e-9)};
  chooser.start(root);
  chooser.visit(root, all);

  TerrainMesh mesh;
  mesh.vertices = chooser.vertices();
  vtkNew<vtkPoints> vtk_points;
  for (const auto& v : mesh.vertices) vtk_points->InsertNextPoint(v.x(), v.y(), v.z());
  vtkNew<vtkPolyData> input;
  input->SetPoints(vtk_points);
  vtkNew<vtkDelaunay2D> delaunay;
  delaunay->SetInputData(input);
  delaunay->Update();
  vtkPolyData* out = delaunay->GetOutput();
  // A triangle is kept when its centre lies over a square that had points.
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c) {
    out->GetCellPoints(c, ids);
    if (ids->GetNumberOfIds() != 3) continue;
    std::array<int, 3> t{int(ids->GetId(0)), int(ids->GetId(1)), int(ids->GetId(2))};
    const Eigen::Vector3d a = mesh.vertices[std::size_t(t[0])],
                          b = mesh.vertices[std::size_t(t[1])],
                          d = mesh.vertices[std::size_t(t[2])];
    if (turn(a.head<2>(), b.head<2>(), d.head<2>()) < 0) std::swap(t[1], t[2]);
    if (!chooser.overData(((a + b + d) / 3).head<2>())) continue;
    mesh.triangles.push_back(t);
  }
  connect(mesh);
  return mesh;
}

TriangleLocator::TriangleLocator(const TerrainMesh& mesh) : mesh_(mesh) {
  if (mesh.triangles.empty()) return;
  Eigen::Vector2d lo = mesh.vertices[0].head<2>(), hi = lo;
  double area = 0;
  for (const auto& v : mesh.vertices) lo = lo.cwiseMin(v.head<2>()), hi = hi.cwiseMax(v.head<2>());
  for (int t = 0; t < int(mesh.size()); ++t) area += mesh.areaXY(t);
  // About one triangle per bin on average.
  cell_ = std::max(1e-3, std::sqrt(area / double(mesh.size())));
  origin_ = lo;
  cols_ = std::max(1, int(std::ceil((hi.x() - lo.x()) / cell_)) + 1);
  rows_ = std::max(1, int(std::ceil((hi.y() - lo.y()) / cell_)) + 1);
  bins_.resize(std::size_t(cols_) * std::size_t(rows_));
  for (int t = 0; t < int(mesh.size()); ++t) {
    Eigen::Vector2d a = mesh.corner(t, 0).head<2>(), b = a;
    for (int k = 1; k < 3; ++k)
      a = a.cwiseMin(mesh.corner(t, k).head<2>()), b = b.cwiseMax(mesh.corner(t, k).head<2>());
    const int c0 = int((a.x() - lo.x()) / cell_), c1 = int((b.x() - lo.x()) / cell_);
    const int r0 = int((a.y() - lo.y()) / cell_), r1 = int((b.y() - lo.y()) / cell_);
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c)
        bins_[std::size_t(r) * std::size_t(cols_) + std::size_t(c)].push_back(t);
  }
}

std::optional<int> TriangleLocator::at(const Eigen::Vector2d& xy) const {
  if (bins_.empty() || !xy.allFinite()) return std::nullopt;
  const double fc = (xy.x() - origin_.x()) / cell_, fr = (xy.y() - origin_.y()) / cell_;
  if (fc < 0 || fr < 0 || fc >= cols_ || fr >= rows_) return std::nullopt;
  for (int t : bins_[std::size_t(int(fr)) * std::size_t(cols_) + std::size_t(int(fc))])
    if (mesh_.containsXY(t, xy)) return t;
  return std::nullopt;
}

}  // namespace ambler::mapping
