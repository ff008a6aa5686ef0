#pragma once

#include <filesystem>

#include "footfall/CostMaps.h"

namespace ambler::footfall {

// Reads the foot, limits and weights of resources/config/footfall.json
// (docs/footfall.md). Missing keys keep their defaults; a malformed file or
// a value out of range throws io::FormatError naming the file and key.
CostMapOptions readFootfallConfig(const std::filesystem::path& path);

}  // namespace ambler::footfall
