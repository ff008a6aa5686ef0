// The mesh reader (io::readPly behind mapping::readMesh) on arbitrary
// files: a malformed or truncated PLY must end in an io::FormatError, never
// a crash, and a mesh it returns has finite vertices and triangles that
// name them.
#include "FuzzSupport.h"
#include "io/FormatError.h"
#include "mapping/MappingFiles.h"

using namespace ambler;

namespace {

std::vector<fuzz::Bytes> seeds() {
  const std::string ascii =
      "ply\nformat ascii 1.0\ncomment seed\nelement vertex 4\nproperty float x\n"
      "property float y\nproperty float z\nproperty uchar red\nelement face 2\n"
      "property list uchar int vertex_indices\nend_header\n"
      "0 0 0 1\n1 0 0 2\n1 1 0.5 3\n0 1 0 4\n3 0 1 2\n3 0 2 3\n";
  mapping::TerrainMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.5}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  const auto binary = fuzz::scratchDir() / "seed.ply";
  mapping::writeMesh(binary, mesh);
  return {fuzz::Bytes(ascii.begin(), ascii.end()), fuzz::readBytes(binary)};
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  fuzz::seedCorpus(*argc, *argv, seeds);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = fuzz::writeScratch("mesh.ply", data, size);
  fuzz::refusalOnly<io::FormatError>([&] {
    const auto mesh = mapping::readMesh(path);
    for (const auto& v : mesh.vertices)
      if (!v.allFinite()) std::abort();
    for (const auto& t : mesh.triangles)
      for (const int i : t)
        if (i < 0 || std::size_t(i) >= mesh.vertices.size()) std::abort();
  });
  return 0;
}
