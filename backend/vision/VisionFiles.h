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

// A grey-level image (PNG, PGM, JPEG, TIFF: whatever OpenCV's imgcodecs
// reads; colour is converted to grey, 16-bit scaled to 0-255). Throws
// io::FormatError naming the file when it cannot be read.
io::FloatImage readGreyImage(const std::filesystem::path& path);

}  // namespace ambler::vision
