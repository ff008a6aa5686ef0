#pragma once

#include <filesystem>

#include "app/gs/WalkSession.h"

namespace ambler::gs {

// ambler-sim or a rover on DDS `domain`, commanded with the operator key
// in `key_file` (docs/link.md). Throws what the link or the key file
// throws, each naming the problem.
RoverConnection ddsConnection(std::uint32_t domain, std::uint32_t rover_id,
                              const std::filesystem::path& key_file);

}  // namespace ambler::gs
