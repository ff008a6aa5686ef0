#pragma once

#include <filesystem>

#include "gait/GaitPlanner.h"

namespace ambler::gait {

// Reads the rover, gait and recovery sections of resources/config/rover.json
// (docs/gait.md) into a context whose footfall options keep their defaults.
// Missing keys keep their defaults; a malformed file or a value out of
// range throws io::FormatError naming the file and key.
GaitContext readRoverConfig(const std::filesystem::path& path);

// What the ground station plans with: rover.json's rover, gait and
// recovery sections and footfall.json (simulation settings are read by the
// simulator, rover/SimulatedRover.h). Errors name the file and key.
GaitContext readGaitContext(const std::filesystem::path& rover_json,
                            const std::filesystem::path& footfall_json);
// The installed configuration: config/rover.json and config/footfall.json
// from the resources (core/Resources.h).
GaitContext readInstalledGaitContext();

}  // namespace ambler::gait
