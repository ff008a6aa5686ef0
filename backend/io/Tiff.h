#pragma once

#include <filesystem>
#include <string>

#include "io/FormatError.h"
#include "io/Image.h"

namespace ambler::io {

// Single-channel TIFF rasters through libtiff. Readers accept strip-organised
// files of exactly the expected sample type and throw FormatError naming the
// file and the problem otherwise (wrong type, several channels, truncated
// data, not a TIFF). Writers write to a temporary file and rename it, so an
// interrupted write never leaves a half file under the final name.
FloatImage readFloatTiff(const std::filesystem::path& path);
ByteImage readByteTiff(const std::filesystem::path& path);
void writeTiff(const std::filesystem::path& path, const FloatImage& image);
void writeTiff(const std::filesystem::path& path, const ByteImage& image);

// Throws FormatError unless `image` (read from `path`) is rows x cols as
// `source` (e.g. "its sidecar") says.
template <typename T>
void requireSize(const Image<T>& image, int rows, int cols, const std::filesystem::path& path,
                 const std::string& source) {
  if (image.rows == rows && image.cols == cols) return;
  throw FormatError("image '" + path.string() + "' is " + std::to_string(image.rows) + "x" +
                    std::to_string(image.cols) + " pixels but " + source + " says " +
                    std::to_string(rows) + "x" + std::to_string(cols));
}

// The largest raster accepted, a guard against absurd header values.
inline constexpr long kMaxTiffPixels = 1L << 28;

}  // namespace ambler::io
