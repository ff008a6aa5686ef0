#include "vision/VisionFiles.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cstdint>
#include <fstream>
#include <vector>

#include "io/ImageHeader.h"
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
  const auto format = io::imageFormat(bytes);
  if (format == io::ImageFormat::kOther) fail("is not PNG, PGM, PPM, JPEG or TIFF");
  const auto pixels = io::declaredPixels(bytes, format);
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
