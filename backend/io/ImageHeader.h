#pragma once

#include <cstdint>
#include <optional>
#include <span>

namespace ambler::io {

// What a camera image's first bytes say, read before any decoder sees it:
// decoders allocate whatever size a header claims.
enum class ImageFormat { kPng, kJpeg, kTiff, kPnm, kOther };

// Told by the magic bytes, not by the file's name. kPnm: PGM or PPM (P2, P3,
// P5, P6).
ImageFormat imageFormat(std::span<const std::uint8_t> bytes);

// Width x height as the header claims it (PNG's IHDR, a PNM's header, the
// first TIFF directory's width and length tags, a JPEG's first start of
// frame); none when the bytes end before saying it.
std::optional<std::uint64_t> declaredPixels(std::span<const std::uint8_t> bytes,
                                            ImageFormat format);

}  // namespace ambler::io
