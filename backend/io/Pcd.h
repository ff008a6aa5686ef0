#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace ambler::io {

// A PCD point cloud (PCL's format, v0.7), read by this project's own strict
// reader: PCL's reader trusts its header (a malformed one made it read past
// its buffer), so no file bytes reach it. docs/formats.md lists what is
// refused.
struct PcdField {
  std::string name;
  int size = 4;     // bytes per element: 1, 2, 4 or 8
  char type = 'F';  // I, U or F
  int count = 1;    // elements
};

struct PcdHeader {
  std::vector<PcdField> fields;
  std::uint64_t width = 0, height = 0, points = 0;
  std::string data;               // ascii, binary or binary_compressed
  std::uint64_t data_offset = 0;  // first byte after the header
  // VIEWPOINT: where the cloud was taken from (tx ty tz qw qx qy qz), when
  // the header says.
  std::optional<std::array<double, 7>> viewpoint;

  std::uint64_t pointBytes() const;
  std::size_t elementsPerPoint() const;
  // The index of the field's first element in a point's values, or -1.
  int column(const std::string& name) const;
};

struct PcdCloud {
  PcdHeader header;
  // Every element of every point as a double, point-major:
  // values[i * header.elementsPerPoint() + column].
  std::vector<double> values;
  // No float element is NaN or infinite (PCL's is_dense).
  bool dense = true;

  double at(std::uint64_t point, int column) const {
    return values[point * header.elementsPerPoint() + std::size_t(column)];
  }
};

// Reads and checks the header: keywords once each, in PCL's order
// (VERSION, FIELDS, SIZE, TYPE, COUNT, WIDTH, HEIGHT, VIEWPOINT, POINTS,
// DATA; COUNT and VIEWPOINT optional), whole numbers, FIELDS, SIZE, TYPE
// and COUNT of one length, POINTS = WIDTH x HEIGHT. Throws io::FormatError
// "<path>: ..." naming the problem. With `require_xyz`, fields x, y and z
// must be there.
PcdHeader readPcdHeader(const std::filesystem::path& path, bool require_xyz);

// The header, then the data: ascii (one line a point, each token a number
// of its field's type), binary (exactly POINTS x point size bytes) or
// binary_compressed (LZF, unpacking to exactly that size).
PcdCloud readPcd(const std::filesystem::path& path, bool require_xyz);

}  // namespace ambler::io
