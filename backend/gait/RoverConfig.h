#pragma once

#include <filesystem>

#include "gait/GaitPlanner.h"

namespace ambler::gait {

// Reads the rover, gait and recovery sections of resources/config/rover.json
// (docs/gait.md) into a context whose footfall options keep their defaults.
// Missing keys keep their defaults; a malformed file or a value out of
// range throws io::FormatError naming the file and key.
GaitContext readRoverConfig(const std::filesystem::path& path);

}  // namespace ambler::gait
