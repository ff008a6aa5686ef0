// The point-cloud reader (io::readPcd behind mapping::readCloud) on
// arbitrary files: a malformed or truncated cloud must end in an
// io::FormatError, never a crash, and what it returns holds finite points.
#include "FuzzSupport.h"
#include "io/FormatError.h"
#include "mapping/MappingFiles.h"

using namespace ambler;

namespace {

std::vector<fuzz::Bytes> seeds() {
  const std::string ascii =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
      "WIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n"
      "0 0 0\n1 0 0.5\n0 1 nan\n";
  const auto binary = fuzz::scratchDir() / "seed.pcd";
  mapping::writeCloud(binary, {{0, 0, 0}, {1, 2, 3}, {-1, 0.5, 2}});
  return {fuzz::Bytes(ascii.begin(), ascii.end()), fuzz::readBytes(binary)};
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  fuzz::seedCorpus(*argc, *argv, seeds);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = fuzz::writeScratch("cloud.pcd", data, size);
  fuzz::refusalOnly<io::FormatError>([&] {
    for (const auto& p : mapping::readCloud(path))
      if (!p.allFinite()) std::abort();
  });
  return 0;
}
