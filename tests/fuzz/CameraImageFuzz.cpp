// The camera-image reader (vision::readGreyImage: the format told by its
// first bytes, then OpenCV's decoders) on arbitrary files: a malformed,
// truncated or oversized image must end in an io::FormatError, never a
// crash, and an image it returns is finite.
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>

#include "FuzzSupport.h"
#include "io/FormatError.h"
#include "vision/VisionFiles.h"

using namespace ambler;

namespace {

std::vector<fuzz::Bytes> seeds() {
  cv::Mat grey(6, 8, CV_8U);
  for (int r = 0; r < grey.rows; ++r)
    for (int c = 0; c < grey.cols; ++c) grey.at<std::uint8_t>(r, c) = std::uint8_t(r * 30 + c);
  std::vector<fuzz::Bytes> out;
  for (const char* ext : {".png", ".pgm", ".tif", ".jpg"}) {
    std::vector<std::uint8_t> bytes;
    cv::imencode(ext, grey, bytes);
    out.push_back(bytes);
  }
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  fuzz::seedCorpus(*argc, *argv, seeds);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = fuzz::writeScratch("camera.img", data, size);
  fuzz::refusalOnly<io::FormatError>([&] {
    const auto image = vision::readGreyImage(path);
    if (image.pixels.size() != std::size_t(image.rows) * std::size_t(image.cols)) std::abort();
    for (const float v : image.pixels)
      if (!std::isfinite(v)) std::abort();
  });
  return 0;
}
