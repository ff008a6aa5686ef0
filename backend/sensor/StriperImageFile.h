#pragma once

#include <filesystem>

#include "io/FormatError.h"
#include "sensor/StriperImage.h"

namespace ambler::sensor {

// A light-striper acquisition as a folder (docs/formats.md): x.tif, y.tif,
// z.tif, intensity.tif (float32, same size) and striper.json with the
// camera model and the projector position. Reading throws io::FormatError.
StriperImage readStriperImage(const std::filesystem::path& folder);
void writeStriperImage(const StriperImage& image, const std::filesystem::path& folder);

// True when `folder` looks like a striper acquisition (has striper.json).
bool isStriperFolder(const std::filesystem::path& folder);

}  // namespace ambler::sensor
