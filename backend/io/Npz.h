#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "io/FormatError.h"

namespace ambler::io {

// One array of a NumPy archive: its shape (empty for a scalar) and its
// values in C order, as doubles.
struct NpyArray {
  std::vector<std::size_t> shape;
  std::vector<double> values;
};

// Every array of a .npz archive (numpy.savez / savez_compressed) by name,
// without ".npy". Little-endian integers and floats of 1-8 bytes in C order
// are read (what NumPy writes on a PC); anything else, a truncated entry or
// a file that is not such an archive is a FormatError naming the file, the
// entry and the problem. The zip is read with minizip.
std::map<std::string, NpyArray> readNpz(const std::filesystem::path& path);

}  // namespace ambler::io
