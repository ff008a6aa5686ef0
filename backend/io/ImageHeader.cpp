#include "io/ImageHeader.h"

#include <algorithm>
#include <cctype>
#include <initializer_list>

namespace ambler::io {

namespace {

using Bytes = std::span<const std::uint8_t>;

bool startsWith(Bytes bytes, std::initializer_list<std::uint8_t> magic) {
  return bytes.size() >= magic.size() && std::equal(magic.begin(), magic.end(), bytes.begin());
}

std::uint64_t bigEndian(Bytes b, std::size_t at, int n) {
  std::uint64_t v = 0;
  for (int k = 0; k < n; ++k) v = v << 8 | b[at + std::size_t(k)];
  return v;
}

std::uint64_t littleEndian(Bytes b, std::size_t at, int n) {
  std::uint64_t v = 0;
  for (int k = n - 1; k >= 0; --k) v = v << 8 | b[at + std::size_t(k)];
  return v;
}

std::optional<std::uint64_t> pngPixels(Bytes b) {
  if (b.size() < 24) return std::nullopt;
  return bigEndian(b, 16, 4) * bigEndian(b, 20, 4);  // IHDR
}

// P2, P3, P5, P6: the magic, then width and height as text, with comments.
std::optional<std::uint64_t> pnmPixels(Bytes b) {
  std::size_t at = 2;
  std::uint64_t size[2] = {0, 0};
  for (auto& v : size) {
    while (at < b.size() && (std::isspace(b[at]) || b[at] == '#'))
      if (b[at] == '#')
        while (at < b.size() && b[at] != '\n') ++at;
      else
        ++at;
    const std::size_t start = at;
    while (at < b.size() && std::isdigit(b[at]) && at - start < 10) v = v * 10 + (b[at++] - '0');
    if (at == start) return std::nullopt;
  }
  return size[0] * size[1];
}

// The first directory's ImageWidth (256) and ImageLength (257) tags.
std::optional<std::uint64_t> tiffPixels(Bytes b) {
  const bool little = b[0] == 'I';
  auto read = [&](std::size_t at, int n) {
    return little ? littleEndian(b, at, n) : bigEndian(b, at, n);
  };
  if (b.size() < 8) return std::nullopt;
  const std::uint64_t ifd = read(4, 4);
  if (ifd + 2 > b.size()) return std::nullopt;
  const std::uint64_t entries = read(ifd, 2);
  std::uint64_t size[2] = {0, 0};
  for (std::uint64_t e = 0; e < entries && ifd + 2 + 12 * (e + 1) <= b.size(); ++e) {
    const std::size_t at = std::size_t(ifd + 2 + 12 * e);
    const std::uint64_t tag = read(at, 2), type = read(at + 2, 2);
    if ((tag == 256 || tag == 257) && (type == 3 || type == 4))
      size[tag - 256] = read(at + 8, type == 3 ? 2 : 4);
  }
  if (size[0] == 0 || size[1] == 0) return std::nullopt;
  return size[0] * size[1];
}

// The first start-of-frame segment's height and width.
std::optional<std::uint64_t> jpegPixels(Bytes b) {
  std::size_t at = 2;
  while (at + 4 <= b.size()) {
    if (b[at] != 0xff) return std::nullopt;
    const std::uint8_t marker = b[at + 1];
    if (marker == 0xff) {
      ++at;  // fill byte
      continue;
    }
    if (marker == 0x01 || (marker >= 0xd0 && marker <= 0xd8)) {
      at += 2;  // no length
      continue;
    }
    const bool frame =
        marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc;
    if (frame)
      return at + 9 <= b.size() ? std::optional(bigEndian(b, at + 5, 2) * bigEndian(b, at + 7, 2))
                                : std::nullopt;
    if (marker == 0xda) return std::nullopt;  // scan data before any frame
    at += 2 + std::size_t(bigEndian(b, at + 2, 2));
  }
  return std::nullopt;
}

}  // namespace

ImageFormat imageFormat(Bytes b) {
  if (startsWith(b, {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'})) return ImageFormat::kPng;
  if (startsWith(b, {0xff, 0xd8, 0xff})) return ImageFormat::kJpeg;
  if (startsWith(b, {'I', 'I', 42, 0}) || startsWith(b, {'M', 'M', 0, 42}))
    return ImageFormat::kTiff;
  if (b.size() >= 2 && b[0] == 'P' && (b[1] == '2' || b[1] == '5' || b[1] == '3' || b[1] == '6'))
    return ImageFormat::kPnm;
  return ImageFormat::kOther;
}

std::optional<std::uint64_t> declaredPixels(Bytes b, ImageFormat format) {
  switch (format) {
    case ImageFormat::kPng:
      return pngPixels(b);
    case ImageFormat::kJpeg:
      return jpegPixels(b);
    case ImageFormat::kTiff:
      return tiffPixels(b);
    case ImageFormat::kPnm:
      return pnmPixels(b);
    default:
      return std::nullopt;
  }
}

}  // namespace ambler::io
