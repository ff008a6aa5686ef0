#pragma once

#include <filesystem>

#include "io/FormatError.h"
#include "io/Image.h"
#include "vision/DangerMap.h"

namespace ambler::vision {

// The camera file of docs/formats.md: the camera model and B, N of eqs.
// 3-4. Throws io::FormatError naming the file, the key and the problem.
struct CameraFile {
  CameraModel camera;
  DangerOptions danger;
};
CameraFile readCameraFile(const std::filesystem::path& json);

// A grey-level image (PNG, PGM/PPM, JPEG or TIFF, told by its first bytes;
// OpenCV's imgcodecs decodes it; colour is converted to grey, 16-bit scaled
// to 0-255), at most 64 million pixels, all finite. Throws io::FormatError
// "<path>: image ..." naming the problem.
io::FloatImage readGreyImage(const std::filesystem::path& path);

}  // namespace ambler::vision
