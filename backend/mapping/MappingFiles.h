#pragma once

#include <filesystem>

#include "mapping/Registration.h"
#include "mapping/TerrainMesh.h"

namespace ambler::mapping {

// Point clouds as PCD (x, y, z fields; PCL's reader), meshes as PLY
// (vertices and triangles; VTK's reader and writer): docs/formats.md.
// Readers throw io::FormatError naming the file and the problem.
Cloud readCloud(const std::filesystem::path& pcd);
void writeCloud(const std::filesystem::path& pcd, const Cloud& cloud);
TerrainMesh readMesh(const std::filesystem::path& ply);
void writeMesh(const std::filesystem::path& ply, const TerrainMesh& mesh);

}  // namespace ambler::mapping
