#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ambler::io {

// The header of a PCD point cloud (PCL's format, v0.7), checked against the
// file before PCL reads it: PCL's reader crashes on some malformed files
// (an empty one, for a start), which must instead be refused with a
// message.
struct PcdHeader {
  std::vector<std::string> fields;
  std::vector<int> sizes;   // bytes per element: 1, 2, 4 or 8
  std::vector<char> types;  // I, U or F
  std::vector<int> counts;  // elements per field
  std::uint64_t width = 0, height = 1, points = 0;
  std::string data;               // ascii, binary or binary_compressed
  std::uint64_t data_offset = 0;  // first byte after the header

  std::uint64_t pointBytes() const;
  bool hasField(const std::string& name) const;
};

// Reads and checks the header and that the file is long enough for its
// points; throws io::FormatError naming the file and the problem. With
// `require_xyz`, fields x, y and z must be there.
PcdHeader checkPcd(const std::filesystem::path& path, bool require_xyz);

}  // namespace ambler::io
