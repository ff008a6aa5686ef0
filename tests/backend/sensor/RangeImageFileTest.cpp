#include "sensor/RangeImageFile.h"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>

#include "TempDir.h"
#include "core/Angles.h"
#include "io/Json.h"
#include "io/Tiff.h"

namespace ambler::sensor {
namespace {

RangeImage sampleImage() {
  RangeImage image;
  image.geometry = ScanGeometry::symmetric(6, 9, 30 * kDeg, 60 * kDeg);
  image.range_sigma_k = 2.5e-4;
  image.sensor_to_world = Eigen::Translation3d(1, 2, 5) *
                          Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                          Eigen::AngleAxisd(-0.5, Eigen::Vector3d::UnitX());
  for (int i = 0; i < 6 * 9; ++i) image.range.push_back(i % 7 == 0 ? 0.0f : 3.0f + 0.25f * i);
  image.range[5] = std::numeric_limits<float>::quiet_NaN();
  return image;
}

TEST(RangeImageFile, RoundTripKeepsEverything) {
  TempDir dir;
  auto image = sampleImage();
  image.reflectance.assign(image.range.size(), 0.5f);
  writeRangeImage(image, dir / "scan.tif");
  ASSERT_TRUE(std::filesystem::exists(dir / "scan.json"));
  const auto back = readRangeImage(dir / "scan.tif");
  EXPECT_EQ(back.rows(), 6);
  EXPECT_EQ(back.cols(), 9);
  EXPECT_NEAR(back.geometry.phi_first, image.geometry.phi_first, 1e-12);
  EXPECT_NEAR(back.geometry.theta_step, image.geometry.theta_step, 1e-12);
  EXPECT_DOUBLE_EQ(back.range_sigma_k, 2.5e-4);
  EXPECT_TRUE(back.sensor_to_world.isApprox(image.sensor_to_world, 1e-12));
  ASSERT_EQ(back.range.size(), image.range.size());
  for (std::size_t i = 0; i < image.range.size(); ++i) {
    if (std::isnan(image.range[i]))
      EXPECT_TRUE(std::isnan(back.range[i]));
    else
      EXPECT_EQ(back.range[i], image.range[i]);
  }
  EXPECT_EQ(back.reflectance, image.reflectance);
  EXPECT_EQ(back.returnCount(), image.returnCount());
  EXPECT_TRUE(back.pointInWorld(2, 3).isApprox(image.pointInWorld(2, 3), 1e-9));
}

// A bad file: how to spoil a good pair, and what the error must say.
struct BadFile {
  std::string name;
  std::function<void(const TempDir&)> spoil;
  std::string expected;
};

void editSidecar(const TempDir& dir, const std::function<void(nlohmann::json&)>& edit) {
  auto json = io::readJsonFile(dir / "scan.json");
  edit(json);
  std::ofstream(dir / "scan.json") << json.dump();
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

std::vector<BadFile> badFiles() {
  return {
      {"MissingTiff", [](auto& d) { std::filesystem::remove(d / "scan.tif"); }, "does not exist"},
      {"MissingSidecar", [](auto& d) { std::filesystem::remove(d / "scan.json"); }, "cannot open"},
      {"MalformedJson", [](auto& d) { writeText(d / "scan.json", "{\"rows\": 6, \"cols\": "); },
       "malformed at byte"},
      {"MissingKey", [](auto& d) { editSidecar(d, [](auto& j) { j.erase("phi_step_deg"); }); },
       "\"phi_step_deg\" is missing"},
      {"WrongType", [](auto& d) { editSidecar(d, [](auto& j) { j["rows"] = "6"; }); },
       "\"rows\" must be an integer"},
      {"NumberTooLarge",
       [](auto& d) { writeText(d / "scan.json", R"({"model":"spherical_polar","rows":1e999})"); },
       "unusable value"},
      {"UnknownModel", [](auto& d) { editSidecar(d, [](auto& j) { j["model"] = "pinhole"; }); },
       "only \"spherical_polar\""},
      {"SizeMismatch", [](auto& d) { editSidecar(d, [](auto& j) { j["rows"] = 7; }); },
       "scan.tif' is 6x9 pixels but its sidecar says 7x9"},
      {"PoseWrongLength",
       [](auto& d) { editSidecar(d, [](auto& j) { j["sensor_to_world"].erase(15); }); },
       "array of 16 numbers"},
      {"PoseNotRigid",
       [](auto& d) {
         editSidecar(d, [](auto& j) {
           j["sensor_to_world"] = {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1};
         });
       },
       "not a rigid transform"},
      {"NullNumber",  // what a writer of NaN as JSON null leaves behind
       [](auto& d) { editSidecar(d, [](auto& j) { j["phi_first_deg"] = nullptr; }); },
       "\"phi_first_deg\" must be a number, found null"},
      {"ZeroStep", [](auto& d) { editSidecar(d, [](auto& j) { j["theta_step_deg"] = 0.0; }); },
       "angular steps must be non-zero"},
      {"ThetaBeyond90",
       [](auto& d) { editSidecar(d, [](auto& j) { j["theta_first_deg"] = -95.0; }); },
       "theta must stay inside"},
      {"PhiBeyondATurn",
       [](auto& d) { editSidecar(d, [](auto& j) { j["phi_first_deg"] = 1e300; }); },
       "phi must stay within -360..360 degrees"},
      {"NotATiff", [](auto& d) { writeText(d / "scan.tif", "this is not an image"); },
       "not a TIFF file"},
      {"TruncatedTiff",
       [](auto& d) {
         const auto size = std::filesystem::file_size(d / "scan.tif");
         std::filesystem::resize_file(d / "scan.tif", size - 60);
       },
       "truncated or corrupt"},
      {"ByteTiff", [](auto& d) { io::writeTiff(d / "scan.tif", io::ByteImage(6, 9, 3)); },
       "expected 32-bit float samples, found 8-bit integer"},
      {"NegativeRange",
       [](auto& d) {
         auto img = io::readFloatTiff(d / "scan.tif");
         img(4, 2) = -1.0f;
         io::writeTiff(d / "scan.tif", img);
       },
       "range at row 4, col 2 is -1"},
  };
}

void PrintTo(const BadFile& bad, std::ostream* os) { *os << bad.name; }

class RangeImageBadFile : public ::testing::TestWithParam<BadFile> {};

TEST_P(RangeImageBadFile, GivesAClearError) {
  TempDir dir;
  writeRangeImage(sampleImage(), dir / "scan.tif");
  GetParam().spoil(dir);
  try {
    readRangeImage(dir / "scan.tif");
    FAIL() << "no error for " << GetParam().name;
  } catch (const io::FormatError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(GetParam().expected), std::string::npos) << message;
    EXPECT_NE(message.find(dir.path().string()), std::string::npos)
        << "the message should name the file: " << message;
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, RangeImageBadFile, ::testing::ValuesIn(badFiles()),
                         [](const auto& info) { return info.param.name; });

TEST(RangeImageFile, RefusesToWriteAnInconsistentImage) {
  TempDir dir;
  auto image = sampleImage();
  image.range.pop_back();
  EXPECT_THROW(writeRangeImage(image, dir / "scan.tif"), io::FormatError);
  EXPECT_FALSE(std::filesystem::exists(dir / "scan.tif"));
}

}  // namespace
}  // namespace ambler::sensor
