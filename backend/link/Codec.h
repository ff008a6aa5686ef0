#pragma once

// One byte form for every message: what the HMAC covers, what the mission
// log stores and what travels inside the DDS samples. Little-endian,
// versioned, every length checked on the way in.

#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include "link/Messages.h"

namespace ambler::link {

// A message that cannot be decoded: truncated, unknown type or version,
// sizes that do not agree, values out of range. The text names the problem.
class DecodeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using Bytes = std::vector<std::uint8_t>;

Bytes encode(const Telemetry& message);
Bytes encode(const Command& command);

// The bytes a command's HMAC covers: the whole command but the signature.
Bytes signedContent(const Command& command);

// Throw DecodeError on anything but a complete, well-formed message.
Telemetry decodeTelemetry(std::span<const std::uint8_t> bytes);
Command decodeCommand(std::span<const std::uint8_t> bytes);

}  // namespace ambler::link
