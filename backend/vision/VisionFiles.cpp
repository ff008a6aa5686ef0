#include "vision/VisionFiles.h"

#include <opencv2/imgcodecs.hpp>

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

io::FloatImage readGreyImage(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path))
    throw io::FormatError("image '" + path.string() + "': file does not exist");
  const cv::Mat raw = cv::imread(path.string(), cv::IMREAD_GRAYSCALE | cv::IMREAD_ANYDEPTH);
  if (raw.empty())
    throw io::FormatError("image '" + path.string() + "': not an image OpenCV can read");
  cv::Mat grey;
  raw.convertTo(grey, CV_32F, raw.depth() == CV_16U ? 255.0 / 65535.0 : 1.0);
  io::FloatImage image(grey.rows, grey.cols);
  for (int r = 0; r < grey.rows; ++r)
    for (int c = 0; c < grey.cols; ++c) image(r, c) = grey.at<float>(r, c);
  return image;
}

}  // namespace ambler::vision
