#pragma once

#include <filesystem>
#include <optional>

#include "mapping/Registration.h"
#include "mapping/TerrainMesh.h"

namespace ambler::mapping {

// Point clouds as PCD (x, y, z fields; PCL's reader), meshes as PLY
// (vertices and triangles; VTK's reader and writer): docs/formats.md.
// Readers throw io::FormatError naming the file and the problem.
Cloud readCloud(const std::filesystem::path& pcd);
// A scan: its points and, from the PCD's VIEWPOINT, where its scanner stood
// in the cloud's frame (PCL writes the origin when nobody set it).
struct ScanFile {
  Cloud points;
  std::optional<Eigen::Vector3d> scanner;
};
ScanFile readScan(const std::filesystem::path& pcd);
void writeCloud(const std::filesystem::path& pcd, const Cloud& cloud,
                const Eigen::Vector3d& scanner = Eigen::Vector3d::Zero());
TerrainMesh readMesh(const std::filesystem::path& ply);
void writeMesh(const std::filesystem::path& ply, const TerrainMesh& mesh);

// A digital elevation model in the layout of matplotlib's sample DEM
// (jacksboro_fault_dem.npz): `elevation` [m], rows x cols of cells, the
// longitudes `xmin`, `xmax` of the grid's outer edges on the side of its
// first and last columns, the latitudes `ymin`, `ymax` of the edges on the
// side of its first and last rows [deg] (their spans over the cell counts
// give the file's dx, dy). Heights are at the cells' centres. Returned as
// points in metres east (x) and north (y) of its centre (equirectangular,
// exact to 0.1 % over 30 km), z the elevation.
Cloud readDem(const std::filesystem::path& npz);

}  // namespace ambler::mapping
