#pragma once

#include <filesystem>

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

// The largest raster accepted, a guard against absurd header values.
inline constexpr long kMaxTiffPixels = 1L << 28;

}  // namespace ambler::io
