#include "io/Ply.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "TempDir.h"
#include "io/FormatError.h"

namespace ambler::io {
namespace {

const std::string kAsciiHead =
    "ply\nformat ascii 1.0\ncomment two triangles\nelement vertex 4\nproperty float x\n"
    "property float y\nproperty float z\nelement face 2\n"
    "property list uchar int vertex_indices\nend_header\n";
const std::string kAsciiBody = "0 0 0\n1 0 0\n1 1 0.5\n0 1 0\n3 0 1 2\n3 0 2 3\n";

class Ply : public ::testing::Test {
 protected:
  std::filesystem::path write(const std::string& content) {
    const auto path = dir_ / "mesh.ply";
    std::ofstream(path, std::ios::binary) << content;
    return path;
  }
  std::string problem(const std::string& content) {
    const auto path = write(content);
    try {
      (void)readPly(path);
    } catch (const FormatError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path.string() + ": PLY ", 0), 0u) << e.what();
      return e.what();
    }
    return "accepted";
  }
  TempDir dir_;
};

TEST_F(Ply, ReadsAsciiMeshes) {
  const auto mesh = readPly(write(kAsciiHead + kAsciiBody));
  ASSERT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.vertices[2], (std::array<double, 3>{1, 1, 0.5}));
  ASSERT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.triangles[1], (std::array<std::int64_t, 3>{0, 2, 3}));
}

// Both byte orders, with a property and an element the mesh does not use.
TEST_F(Ply, ReadsBinaryMeshesInEitherByteOrder) {
  for (const bool big : {false, true}) {
    std::string body;
    auto put = [&](auto v) {
      char b[sizeof v];
      std::memcpy(b, &v, sizeof v);
      if (big) std::reverse(b, b + sizeof v);
      body.append(b, sizeof v);
    };
    for (int i = 0; i < 3; ++i)
      put(double(i)), put(float(2 * i)), put(float(-i)), put(std::uint16_t(9));
    put(std::uint8_t(3)), put(std::int32_t(2)), put(std::int32_t(0)), put(std::int32_t(1));
    put(std::int8_t(5));
    const auto mesh = readPly(
        write(std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
              " 1.0\nelement vertex 3\nproperty double x\nproperty float y\nproperty float z\n"
              "property ushort confidence\nelement face 1\nproperty list uchar int vertex_indices\n"
              "element camera 1\nproperty char view\nend_header\n" +
              body));
    ASSERT_EQ(mesh.vertices.size(), 3u) << big;
    EXPECT_EQ(mesh.vertices[2], (std::array<double, 3>{2, 4, -2})) << big;
    EXPECT_EQ(mesh.triangles[0], (std::array<std::int64_t, 3>{2, 0, 1})) << big;
  }
}

TEST_F(Ply, RefusesMalformedHeaders) {
  EXPECT_NE(problem("").find("does not start with 'ply'"), std::string::npos);
  EXPECT_NE(problem("ply\nformat ascii 1.0\nelement vertex 4\n").find("before end_header"),
            std::string::npos);
  EXPECT_NE(problem("ply\nformat ascii 2.0\nend_header\n").find("format line"), std::string::npos);
  EXPECT_NE(problem("ply\nformat ascii 1.0\nelement vertex -4\nend_header\n").find("element line"),
            std::string::npos);
  EXPECT_NE(problem("ply\nformat ascii 1.0\nelement vertex 999999999999\nend_header\n")
                .find("more than 200000000"),
            std::string::npos);
  EXPECT_NE(problem("ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n")
                .find("property line"),
            std::string::npos);
  EXPECT_NE(
      problem("ply\nformat ascii 1.0\nproperty float x\nend_header\n").find("before any element"),
      std::string::npos);
  EXPECT_NE(problem("ply\nformat ascii 1.0\nelement vertex 2\nend_header\n")
                .find("vertex has items but no properties"),
            std::string::npos);
  EXPECT_NE(problem("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                    "element face 0\nproperty list uchar int vertex_indices\nend_header\n")
                .find("no scalar property z"),
            std::string::npos);
  EXPECT_NE(problem("ply\nelement vertex 1\nend_header\n").find("no format line"),
            std::string::npos);
  EXPECT_NE(problem("ply\nformat ascii 1.0\nbogus\nend_header\n").find("unknown header line"),
            std::string::npos);
}

TEST_F(Ply, RefusesBodiesThatDisagreeWithTheHeader) {
  EXPECT_EQ(problem(kAsciiHead + kAsciiBody), "accepted");
  EXPECT_NE(problem(kAsciiHead + "0 0 0\n1 0 0\n1 1 0.5\n0 1 0\n3 0 1 2\n")
                .find("truncated in face 1 of 2"),
            std::string::npos);
  EXPECT_NE(problem(kAsciiHead + kAsciiBody + "7\n").find("more values"), std::string::npos);
  EXPECT_NE(problem(kAsciiHead + "0 0 0\n1 0 0\n1 1 nan\n0 1 0\n3 0 1 2\n3 0 2 3\n")
                .find("vertex 2 is not finite"),
            std::string::npos);
  EXPECT_NE(problem(kAsciiHead + "0 0 0\n1 0 0\n1 1 0.5\n0 1 0\n4 0 1 2 3\n3 0 2 3\n")
                .find("face 0 is not a triangle (4 vertices)"),
            std::string::npos);
  EXPECT_NE(problem(kAsciiHead + "0 0 0\n1 0 0\n1 1 0.5\n0 1 0\n3 0 1 2\n3 0 2 4\n")
                .find("names vertex 4 of 4"),
            std::string::npos);
  EXPECT_NE(problem(kAsciiHead + "0 0 0\n1 0 0\n1 1 0.5\n0 1 0\n3 0 1 2\n3 0 0 3\n")
                .find("face 1 names a vertex twice"),
            std::string::npos);
  EXPECT_NE(
      problem(kAsciiHead + "0 0 0\n1 0 0\n1 1 0.5\n0 1 0\n3 0 1 2\n3 0 2.5 3\n").find("'2.5'"),
      std::string::npos);
  EXPECT_NE(problem("ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                    "property float y\nproperty float z\nelement face 0\n"
                    "property list uchar int vertex_indices\nend_header\n" +
                    std::string(20, '\0'))
                .find("truncated in vertex 1 of 3"),
            std::string::npos);
}

}  // namespace
}  // namespace ambler::io
