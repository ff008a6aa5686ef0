#include "vision/VisionFiles.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <optional>
#include <vector>

#include "io/Json.h"

namespace ambler::vision {

CameraFile readCameraFile(const std::filesystem::path& json) {
  const auto value = io::readJsonFile(json);
  const io::JsonFields f(value, "camera '" + json.string() + "'");
  CameraFile file;
  auto& c = file.camera;
  c.rows = f.integer("rows");
  c.alpha_deg = f.number("alpha_deg");
  c.beta_deg = f.number("beta_deg");
  c.height_m = f.number("height_m");
  c.wheel_diameter_m = f.number("wheel_diameter_m");
  c.rover_diagonal_m = f.number("rover_diagonal_m");
  try {
    validate(c);
  } catch (const std::invalid_argument& e) {
    throw io::FormatError("camera '" + json.string() + "': " + e.what());
  }
  file.danger.variance_threshold = f.number("variance_threshold");
  if (file.danger.variance_threshold <= 0) f.fail("variance_threshold", "must be positive");
  file.danger.max_brightness = f.number("max_brightness");
  if (file.danger.max_brightness <= 0) f.fail("max_brightness", "must be positive");
  return file;
}

namespace {

// Larger than any camera this station drives; OpenCV's own limit is 2^30.
constexpr std::uint64_t kMaxPixels = 64'000'000;
constexpr std::uintmax_t kMaxFileBytes = 1'000'000'000;

using Bytes = std::vector<std::uint8_t>;

bool startsWith(const Bytes& bytes, std::initializer_list<std::uint8_t> magic) {
  return bytes.size() >= magic.size() && std::equal(magic.begin(), magic.end(), bytes.begin());
}

std::uint64_t bigEndian(const Bytes& b, std::size_t at, int n) {
  std::uint64_t v = 0;
  for (int k = 0; k < n; ++k) v = v << 8 | b[at + std::size_t(k)];
  return v;
}

std::uint64_t littleEndian(const Bytes& b, std::size_t at, int n) {
  std::uint64_t v = 0;
  for (int k = n - 1; k >= 0; --k) v = v << 8 | b[at + std::size_t(k)];
  return v;
}

std::optional<std::uint64_t> pngPixels(const Bytes& b) {
  if (b.size() < 24) return std::nullopt;
  return bigEndian(b, 16, 4) * bigEndian(b, 20, 4);  // IHDR
}

// P2, P3, P5, P6: the magic, then width and height as text, with comments.
std::optional<std::uint64_t> pnmPixels(const Bytes& b) {
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
std::optional<std::uint64_t> tiffPixels(const Bytes& b) {
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
std::optional<std::uint64_t> jpegPixels(const Bytes& b) {
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

enum class Format { kPng, kJpeg, kTiff, kPnm, kOther };

// Told by the first bytes, not by the file's name.
Format formatOf(const Bytes& b) {
  if (startsWith(b, {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'})) return Format::kPng;
  if (startsWith(b, {0xff, 0xd8, 0xff})) return Format::kJpeg;
  if (startsWith(b, {'I', 'I', 42, 0}) || startsWith(b, {'M', 'M', 0, 42})) return Format::kTiff;
  if (b.size() >= 2 && b[0] == 'P' && (b[1] == '2' || b[1] == '5' || b[1] == '3' || b[1] == '6'))
    return Format::kPnm;
  return Format::kOther;
}

// The size a header claims, checked before a decoder allocates it.
std::optional<std::uint64_t> declaredPixels(const Bytes& b, Format format) {
  switch (format) {
    case Format::kPng:
      return pngPixels(b);
    case Format::kJpeg:
      return jpegPixels(b);
    case Format::kTiff:
      return tiffPixels(b);
    case Format::kPnm:
      return pnmPixels(b);
    default:
      return std::nullopt;
  }
}

}  // namespace

io::FloatImage readGreyImage(const std::filesystem::path& path) {
  auto fail = [&](const std::string& problem) {
    throw io::FormatError(path.string() + ": image " + problem);
  };
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail("file does not exist");
  if (std::filesystem::file_size(path, ec) > kMaxFileBytes) fail("file is over 1 GB");
  std::ifstream in(path, std::ios::binary);
  const std::vector<std::uint8_t> bytes(std::istreambuf_iterator<char>(in), {});
  const Format format = formatOf(bytes);
  if (format == Format::kOther) fail("is not PNG, PGM, PPM, JPEG or TIFF");
  const auto pixels = declaredPixels(bytes, format);
  if (!pixels) fail("is truncated or corrupt: its header gives no size");
  if (*pixels > kMaxPixels) fail("has more than 64 million pixels");
  cv::Mat raw;
  try {
    raw = cv::imdecode(bytes, cv::IMREAD_GRAYSCALE | cv::IMREAD_ANYDEPTH);
  } catch (const cv::Exception& e) {
    fail(std::string("cannot be decoded: ") + e.err);
  }
  if (raw.empty()) fail("is truncated or corrupt: the decoder read no picture from it");
  if (std::uint64_t(raw.rows) * std::uint64_t(raw.cols) > kMaxPixels)
    fail("has more than 64 million pixels");
  cv::Mat grey;
  raw.convertTo(grey, CV_32F, raw.depth() == CV_16U ? 255.0 / 65535.0 : 1.0);
  if (!cv::checkRange(grey)) fail("has pixels that are NaN or infinite");
  io::FloatImage image(grey.rows, grey.cols);
  for (int r = 0; r < grey.rows; ++r)
    for (int c = 0; c < grey.cols; ++c) image(r, c) = grey.at<float>(r, c);
  return image;
}

}  // namespace ambler::vision
