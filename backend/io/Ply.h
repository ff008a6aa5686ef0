#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace ambler::io {

// A triangle mesh from a PLY file (ascii, binary_little_endian or
// binary_big_endian 1.0), read by this project's own strict reader: VTK's
// PLY reader trusts the header's counts and sizes, so no file bytes reach
// it. The `vertex` element must have x, y and z; the `face` element a list
// `vertex_indices` (or `vertex_index`) of three indices each, every index
// naming a vertex. Other elements and properties are read past. Throws
// io::FormatError "<path>: PLY ..." naming the problem.
struct PlyMesh {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<std::int64_t, 3>> triangles;
};

PlyMesh readPly(const std::filesystem::path& path);

}  // namespace ambler::io
