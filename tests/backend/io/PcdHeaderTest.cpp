#include "io/PcdHeader.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "TempDir.h"
#include "io/FormatError.h"

namespace ambler::io {
namespace {

std::string header(const std::string& fields_to_data) {
  return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n" + fields_to_data;
}

const std::string kXyz = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";

std::string binaryPoints(int n) {
  std::string bytes(std::size_t(n) * 12, '\0');
  for (int i = 0; i < n * 3; ++i) {
    const float v = float(i);
    std::memcpy(&bytes[std::size_t(i) * 4], &v, 4);
  }
  return bytes;
}

class Pcd : public ::testing::Test {
 protected:
  std::filesystem::path write(const std::string& content) {
    const auto path = dir_ / "cloud.pcd";
    std::ofstream(path, std::ios::binary) << content;
    return path;
  }
  // The problem named in the error, with the file's name.
  std::string problem(const std::string& content, bool require_xyz = true) {
    try {
      checkPcd(write(content), require_xyz);
    } catch (const FormatError& e) {
      EXPECT_NE(std::string(e.what()).find("cloud.pcd"), std::string::npos) << e.what();
      return e.what();
    }
    return "accepted";
  }
  TempDir dir_;
};

TEST_F(Pcd, AcceptsAsciiAndBinaryClouds) {
  const auto ascii = checkPcd(
      write(header(kXyz + "WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n"
                          "0 0 0\n1 2 3\n")),
      true);
  EXPECT_EQ(ascii.points, 2u);
  EXPECT_EQ(ascii.pointBytes(), 12u);
  const auto binary = checkPcd(
      write(header(kXyz + "WIDTH 3\nHEIGHT 2\nPOINTS 6\nDATA binary\n") + binaryPoints(6)), true);
  EXPECT_EQ(binary.points, 6u);
  EXPECT_EQ(binary.data, "binary");
  EXPECT_TRUE(binary.hasField("z"));
}

TEST_F(Pcd, RefusesMalformedHeadersNamingTheProblem) {
  const std::string pts = "WIDTH 2\nHEIGHT 1\nPOINTS 2\n";
  EXPECT_NE(problem("").find("empty"), std::string::npos);
  EXPECT_NE(problem(header(kXyz + pts)).find("before its DATA line"), std::string::npos);
  EXPECT_NE(problem(header("FIELDS x y z\nSIZE 4 4\nTYPE F F F\n" + pts + "DATA ascii\n"))
                .find("different numbers"),
            std::string::npos);
  EXPECT_NE(
      problem(header("FIELDS x y\nSIZE 4 4\nTYPE F F\n" + pts + "DATA ascii\n")).find("no field z"),
      std::string::npos);
  // Without the need for x, y, z (ambler-cli info) the same cloud is fine.
  EXPECT_EQ(
      problem(header("FIELDS x y\nSIZE 4 4\nTYPE F F\n" + pts + "DATA ascii\n1 2\n3 4\n"), false),
      "accepted");
  EXPECT_NE(problem(header(kXyz + "WIDTH 2\nHEIGHT 2\nPOINTS 3\nDATA ascii\n")).find("POINTS"),
            std::string::npos);
  EXPECT_NE(problem(header(kXyz + "WIDTH 0\nHEIGHT 1\nPOINTS 0\nDATA ascii\n")).find("no points"),
            std::string::npos);
  EXPECT_NE(problem(header(kXyz + "WIDTH 99999999999\nHEIGHT 1\nDATA ascii\n")).find("more than"),
            std::string::npos);
  EXPECT_NE(problem(header("FIELDS x y z\nSIZE 4 4 3\nTYPE F F F\n" + pts + "DATA ascii\n"))
                .find("SIZE 3"),
            std::string::npos);
  EXPECT_NE(problem(header(kXyz + pts + "DATA zipped\n")).find("DATA 'zipped'"), std::string::npos);
  EXPECT_NE(problem(header(kXyz + "COLOUR red\n" + pts + "DATA ascii\n")).find("unknown header"),
            std::string::npos);
}

TEST_F(Pcd, RefusesTruncatedData) {
  const std::string head = header(kXyz + "WIDTH 4\nHEIGHT 1\nPOINTS 4\n");
  EXPECT_EQ(problem(head + "DATA binary\n" + binaryPoints(4)), "accepted");
  EXPECT_NE(problem(head + "DATA binary\n" + binaryPoints(3)).find("48 bytes"), std::string::npos);
  EXPECT_NE(problem(head + "DATA binary_compressed\n" + "\x05").find("no compressed block"),
            std::string::npos);
  // Compressed size 100 with 4 bytes left; then an unpacked size that does
  // not fit the points.
  std::string sizes(8, '\0');
  sizes[0] = 100, sizes[4] = 48;
  EXPECT_NE(problem(head + "DATA binary_compressed\n" + sizes + "abcd").find("longer than"),
            std::string::npos);
  sizes[0] = 4, sizes[4] = 40;
  EXPECT_NE(problem(head + "DATA binary_compressed\n" + sizes + "abcd").find("unpacks to 40"),
            std::string::npos);
}

}  // namespace
}  // namespace ambler::io
