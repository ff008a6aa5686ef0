#include "sensor/StriperImageFile.h"

#include <gtest/gtest.h>

#include "TempDir.h"
#include "io/Tiff.h"

namespace ambler::sensor {
namespace {

StriperImage sampleStriper() {
  StriperImage s;
  s.camera.rows = 4;
  s.camera.cols = 5;
  s.camera.fx = s.camera.fy = 200;
  s.camera.cx = 2;
  s.camera.cy = 1.5;
  s.camera.camera_to_world.translation() = Eigen::Vector3d(0, -0.6, 1.1);
  s.projector_position = {0.35, -0.6, 1.1};
  for (int i = 0; i < 20; ++i) {
    const bool shadow = i == 7;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    s.x.push_back(shadow ? nan : 0.01f * i);
    s.y.push_back(shadow ? nan : -0.02f * i);
    s.z.push_back(shadow ? nan : 0.003f * i);
    s.intensity.push_back(0.05f * i);
  }
  return s;
}

// A pixel's ray, followed any distance, projects back onto that pixel;
// what lies behind the camera is not in front of it.
TEST(PinholeCamera, APixelsRayProjectsBackOntoIt) {
  PinholeCamera cam;
  cam.rows = 480, cam.cols = 640;
  cam.fx = 520.0, cam.fy = 515.0, cam.cx = 321.5, cam.cy = 238.25;
  cam.camera_to_world = Eigen::Translation3d(0.2, -0.1, 1.5) *
                        Eigen::AngleAxisd(2.6, Eigen::Vector3d(0.3, 1.0, 0.2).normalized());
  for (const auto& [r, c] : {std::pair{0.0, 0.0}, {240.0, 320.0}, {479.0, 12.5}}) {
    const Eigen::Vector3d world = cam.center() + 1.7 * cam.rayInWorld(r, c);
    const Eigen::Vector2d pixel = cam.pixelOf(world);
    EXPECT_NEAR(pixel.x(), c, 1e-9);
    EXPECT_NEAR(pixel.y(), r, 1e-9);
    EXPECT_TRUE(cam.inFront(world));
    EXPECT_FALSE(cam.inFront(cam.center() - 1.7 * cam.rayInWorld(r, c)));
  }
}

TEST(StriperImageFile, RoundTrip) {
  TempDir dir;
  const auto image = sampleStriper();
  writeStriperImage(image, dir / "striper");
  ASSERT_TRUE(isStriperFolder(dir / "striper"));
  const auto back = readStriperImage(dir / "striper");
  EXPECT_EQ(back.rows(), 4);
  EXPECT_EQ(back.cols(), 5);
  EXPECT_EQ(back.pointCount(), 19);
  EXPECT_FALSE(back.hasPoint(1, 2));
  EXPECT_TRUE(back.point(3, 4).isApprox(image.point(3, 4)));
  EXPECT_EQ(back.intensity, image.intensity);
  EXPECT_TRUE(back.camera.camera_to_world.isApprox(image.camera.camera_to_world));
  EXPECT_DOUBLE_EQ(back.camera.fx, 200);
  EXPECT_TRUE(back.projector_position.isApprox(image.projector_position));
}

TEST(StriperImageFile, PlaneOfTheWrongSizeIsNamed) {
  TempDir dir;
  writeStriperImage(sampleStriper(), dir.path());
  io::writeTiff(dir / "z.tif", io::FloatImage(4, 6, 0.0f));
  try {
    readStriperImage(dir.path());
    FAIL();
  } catch (const io::FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("z.tif' is 4x6 pixels but the header says 4x5"),
              std::string::npos)
        << e.what();
  }
}

TEST(StriperImageFile, PartialNanTripleIsRejected) {
  TempDir dir;
  writeStriperImage(sampleStriper(), dir.path());
  auto y = io::readFloatTiff(dir / "y.tif");
  y(1, 2) = 0.5f;  // pixel 7 had NaN in X, Y and Z
  io::writeTiff(dir / "y.tif", y);
  EXPECT_THROW(
      {
        try {
          readStriperImage(dir.path());
        } catch (const io::FormatError& e) {
          EXPECT_NE(std::string(e.what()).find("partial X/Y/Z triple"), std::string::npos);
          throw;
        }
      },
      io::FormatError);
}

TEST(StriperImageFile, MissingPlaneIsNamed) {
  TempDir dir;
  writeStriperImage(sampleStriper(), dir.path());
  std::filesystem::remove(dir / "intensity.tif");
  try {
    readStriperImage(dir.path());
    FAIL();
  } catch (const io::FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("intensity.tif': file does not exist"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace ambler::sensor
