#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <vector>

namespace ambler::mapping {

// bakambu-csa §3: an irregular triangulated mesh of the terrain (2.5-D:
// triangles over the x-y plane, one height per vertex), at variable
// resolution: few large triangles where the ground is flat, many small ones
// where it is rough.
struct TerrainMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;  // counter-clockwise seen from above
  // neighbours[t][k]: the triangle across the edge opposite corner k, or -1.
  std::vector<std::array<int, 3>> neighbours;

  std::size_t size() const { return triangles.size(); }
  Eigen::Vector3d corner(int t, int k) const {
    return vertices[std::size_t(triangles[std::size_t(t)][std::size_t(k)])];
  }
  Eigen::Vector3d centre(int t) const;
  Eigen::Vector3d normal(int t) const;  // unit, upward
  double slopeRad(int t) const;         // of the triangle's plane from the horizontal
  double areaXY(int t) const;           // of its projection [m^2]
  // The point of triangle t's plane above (x, y).
  Eigen::Vector3d pointOn(int t, const Eigen::Vector2d& xy) const;
  // Whether (x, y) lies in triangle t's projection (edges included).
  bool containsXY(int t, const Eigen::Vector2d& xy) const;
};

// Fills mesh.neighbours from the triangles' shared edges.
void connect(TerrainMesh& mesh);

struct MeshOptions {
  // A square of the ground becomes two triangles when a plane fits all its
  // points within this [m]; else it is split in four. Above the range
  // noise (2 cm at 10 m for the simulated scanner), or noise alone splits
  // the ground into its smallest squares.
  double tolerance_m = 0.05;
  double min_cell_m = 0.2;  // squares are not split below this size [m]
  double max_cell_m = 3.2;  // nor kept above it [m]
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const MeshOptions& options);

// Delaunay triangulation (VTK's vtkDelaunay2D, as the paper) of vertices
// chosen by a quadtree over the points: a square whose points a plane fits
// within the tolerance contributes its four corners (on that plane); a
// rough square is split down to min_cell_m, where it contributes its
// points' mean. Triangles over squares without points are dropped, so gaps
// in the data stay gaps. Throws std::invalid_argument for fewer than 3
// finite points.
TerrainMesh triangulate(const std::vector<Eigen::Vector3d>& points,
                        const MeshOptions& options = {});

// Finds the triangle under (x, y) through a grid of triangle bounds.
class TriangleLocator {
 public:
  explicit TriangleLocator(const TerrainMesh& mesh);
  std::optional<int> at(const Eigen::Vector2d& xy) const;

 private:
  const TerrainMesh& mesh_;
  Eigen::Vector2d origin_{0, 0};
  double cell_ = 1.0;
  int cols_ = 0, rows_ = 0;
  std::vector<std::vector<int>> bins_;
};

}  // namespace ambler::mapping
