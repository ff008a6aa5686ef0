#pragma once

#include <cstddef>
#include <vector>

namespace ambler::io {

// A single-channel raster, row-major, as stored in the project's TIFF files.
template <typename T>
struct Image {
  int rows = 0;
  int cols = 0;
  std::vector<T> pixels;

  Image() = default;
  Image(int r, int c, T fill = T{}) : rows(r), cols(c), pixels(std::size_t(r) * c, fill) {}

  T& operator()(int r, int c) { return pixels[std::size_t(r) * cols + c]; }
  const T& operator()(int r, int c) const { return pixels[std::size_t(r) * cols + c]; }
};

using FloatImage = Image<float>;
using ByteImage = Image<unsigned char>;

}  // namespace ambler::io
