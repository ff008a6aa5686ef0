#include "vision/VisionFiles.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <fstream>
#include <iterator>

#include "TempDir.h"

namespace ambler::vision {
namespace {

class GreyImageFile : public ::testing::Test {
 protected:
  std::filesystem::path write(const std::string& name, const std::vector<std::uint8_t>& bytes) {
    const auto path = dir_ / name;
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    return path;
  }
  std::vector<std::uint8_t> encoded(const char* ext, const cv::Mat& image) {
    std::vector<std::uint8_t> bytes;
    EXPECT_TRUE(cv::imencode(ext, image, bytes));
    return bytes;
  }
  std::string problem(const std::filesystem::path& path) {
    try {
      (void)readGreyImage(path);
    } catch (const io::FormatError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path.string() + ": image ", 0), 0u) << e.what();
      return e.what();
    }
    return "accepted";
  }
  TempDir dir_;
};

TEST_F(GreyImageFile, ReadsEachFormatByItsBytesNotItsName) {
  cv::Mat grey(3, 4, CV_8U);
  for (int i = 0; i < 12; ++i) grey.at<std::uint8_t>(i / 4, i % 4) = std::uint8_t(i * 20);
  for (const char* ext : {".png", ".pgm", ".tif"}) {
    const auto image =
        readGreyImage(write(std::string("camera") + ext + ".bin", encoded(ext, grey)));
    ASSERT_EQ(image.rows, 3) << ext;
    ASSERT_EQ(image.cols, 4) << ext;
    EXPECT_EQ(image(2, 3), 220.0f) << ext;
  }
  cv::Mat wide(2, 2, CV_16U, cv::Scalar(65535));
  EXPECT_FLOAT_EQ(readGreyImage(write("wide.png", encoded(".png", wide)))(1, 1), 255.0f);
}

TEST_F(GreyImageFile, RefusesHostileFilesNamingTheProblem) {
  EXPECT_NE(problem(dir_ / "missing.png").find("does not exist"), std::string::npos);
  EXPECT_NE(problem(write("empty.png", {})).find("is not PNG, PGM, PPM, JPEG or TIFF"),
            std::string::npos);
  const std::string text = "<svg>not a camera image</svg>";
  EXPECT_NE(problem(write("text.png", {text.begin(), text.end()})).find("is not PNG"),
            std::string::npos);

  cv::Mat grey(40, 50, CV_8U, cv::Scalar(100));
  auto png = encoded(".png", grey);
  const std::vector<std::uint8_t> cut(png.begin(), png.begin() + 40);
  EXPECT_NE(problem(write("cut.png", cut)).find("truncated or corrupt"), std::string::npos);

  // An IHDR claiming 100000 x 100000 pixels: refused before decoding.
  auto huge = png;
  for (const int at : {16, 20})
    huge[at] = 0, huge[at + 1] = 0x01, huge[at + 2] = 0x86, huge[at + 3] = 0xa0;
  EXPECT_NE(problem(write("huge.png", huge)).find("more than 64 million pixels"),
            std::string::npos);

  // The same claim in each other format's header: a PGM, a TIFF directory
  // of width and length tags, a JPEG's start of frame.
  const std::string pgm = "P5\n# a comment\n100000 100000\n255\n";
  EXPECT_NE(problem(write("huge.pgm", {pgm.begin(), pgm.end()})).find("more than 64 million"),
            std::string::npos);
  const std::vector<std::uint8_t> tiff = {'I', 'I', 42, 0, 8, 0, 0,    0,    2, 0, 0, 1,
                                          4,   0,   1,  0, 0, 0, 0xa0, 0x86, 1, 0, 1, 1,
                                          4,   0,   1,  0, 0, 0, 0xa0, 0x86, 1, 0};
  EXPECT_NE(problem(write("huge.tif", tiff)).find("more than 64 million"), std::string::npos);
  auto jpeg = encoded(".jpg", grey);
  const std::uint8_t start_of_frame[] = {0xff, 0xc0};
  const auto sof =
      std::search(jpeg.begin(), jpeg.end(), std::begin(start_of_frame), std::end(start_of_frame));
  ASSERT_NE(sof, jpeg.end());
  std::fill(sof + 5, sof + 9, std::uint8_t(0xff));  // 65535 x 65535
  EXPECT_NE(problem(write("huge.jpg", jpeg)).find("more than 64 million"), std::string::npos);
  const std::vector<std::uint8_t> no_size = {'I', 'I', 42, 0, 8, 0, 0, 0, 0, 0};
  EXPECT_NE(problem(write("nosize.tif", no_size)).find("its header gives no size"),
            std::string::npos);
  // Found by fuzz_camera_image (corpus tiff-magic-only.tif): the size peek
  // read the directory offset of a TIFF cut after its magic.
  EXPECT_NE(problem(write("magic.tif", {'I', 'I', 42, 0})).find("its header gives no size"),
            std::string::npos);

  cv::Mat floats(2, 2, CV_32F, cv::Scalar(1.0f));
  floats.at<float>(0, 1) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(problem(write("nan.tif", encoded(".tif", floats))).find("NaN or infinite"),
            std::string::npos);
}

}  // namespace
}  // namespace ambler::vision
