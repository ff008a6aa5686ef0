#pragma once

#include <filesystem>
#include <string>

namespace ambler {

// Locates a file shipped in resources/ (configuration, sample data).
// Searched in order: $AMBLER_DATA_DIR, <dir of this program>/../share/ambler,
// the source tree's resources/. Throws std::runtime_error listing the places
// tried when the file is in none of them.
std::filesystem::path findResource(const std::string& relative_path);

}  // namespace ambler
