#pragma once

#include <filesystem>

#include "io/FormatError.h"
#include "sensor/RangeImage.h"

namespace ambler::sensor {

// The range-image file pair of docs/formats.md: a single-channel float32
// TIFF of ranges [m] and a JSON sidecar with the same basename describing
// the spherical-polar geometry, the noise constant and the sensor pose.
// Reading throws io::FormatError naming the file and the problem.
RangeImage readRangeImage(const std::filesystem::path& tiff_path);
void writeRangeImage(const RangeImage& image, const std::filesystem::path& tiff_path);

std::filesystem::path sidecarPath(const std::filesystem::path& tiff_path);

}  // namespace ambler::sensor
