#include "io/Pcd.h"

#include <gtest/gtest.h>
#include <pcl/io/lzf.h>

#include <cmath>
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

// n points, point-major, coordinates 0, 1, 2, ... as float32.
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
  // The problem named in the error, which starts with the file's path.
  std::string problem(const std::string& content, bool require_xyz = true) {
    const auto path = write(content);
    try {
      (void)readPcd(path, require_xyz);
    } catch (const FormatError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path.string() + ": PCD ", 0), 0u) << e.what();
      return e.what();
    }
    return "accepted";
  }
  TempDir dir_;
};

TEST_F(Pcd, ReadsAsciiAndBinaryClouds) {
  const auto ascii = readPcd(
      write(header(kXyz + "WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n"
                          "0 0 0\n1 2.5 -3e2\n")),
      true);
  EXPECT_EQ(ascii.header.points, 2u);
  EXPECT_EQ(ascii.header.pointBytes(), 12u);
  EXPECT_EQ(ascii.at(1, ascii.header.column("y")), 2.5);
  EXPECT_EQ(ascii.at(1, ascii.header.column("z")), -300.0);
  EXPECT_TRUE(ascii.dense);

  const auto binary = readPcd(
      write(header(kXyz + "WIDTH 3\nHEIGHT 2\nPOINTS 6\nDATA binary\n") + binaryPoints(6)), true);
  EXPECT_EQ(binary.header.points, 6u);
  EXPECT_EQ(binary.header.data, "binary");
  for (int i = 0; i < 6; ++i)
    for (int a = 0; a < 3; ++a) EXPECT_EQ(binary.at(std::uint64_t(i), a), double(i * 3 + a));
}

TEST_F(Pcd, ReadsMixedTypesCountsAndNan) {
  // x y z float, an rgb packed as U4, a 2-element I2 field, a double.
  std::string body;
  auto put = [&](auto v) { body.append(reinterpret_cast<const char*>(&v), sizeof v); };
  for (int i = 0; i < 2; ++i) {
    put(float(i)), put(float(-i)), put(i == 1 ? NAN : 0.5f);
    put(std::uint32_t(0xff0000u + std::uint32_t(i)));
    put(std::int16_t(-7)), put(std::int16_t(i));
    put(double(1e10 + i));
  }
  const auto c = readPcd(
      write(header("FIELDS x y z rgb n t\nSIZE 4 4 4 4 2 8\nTYPE F F F U I F\nCOUNT 1 1 1 1 2 1\n"
                   "WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA binary\n") +
            body),
      true);
  EXPECT_EQ(c.header.elementsPerPoint(), 7u);
  EXPECT_EQ(c.header.column("n"), 4);
  EXPECT_EQ(c.header.column("t"), 6);
  EXPECT_EQ(c.at(1, 3), double(0xff0001u));
  EXPECT_EQ(c.at(1, 4), -7.0);
  EXPECT_EQ(c.at(1, 5), 1.0);
  EXPECT_EQ(c.at(1, 6), 1e10 + 1);
  EXPECT_TRUE(std::isnan(c.at(1, 2)));
  EXPECT_FALSE(c.dense);
}

TEST_F(Pcd, ReadsBinaryCompressedThroughLzf) {
  // PCL's layout: all x, then all y, then all z, LZF-compressed.
  const int n = 50;
  std::string soa(std::size_t(n) * 12, '\0');
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < n; ++i) {
      const float v = float(a * 1000 + i % 7);
      std::memcpy(&soa[std::size_t(a * n + i) * 4], &v, 4);
    }
  std::string packed(soa.size() * 2, '\0');
  const unsigned size =
      pcl::lzfCompress(soa.data(), unsigned(soa.size()), packed.data(), unsigned(packed.size()));
  ASSERT_GT(size, 0u);
  packed.resize(size);
  std::string sizes(8, '\0');
  const std::uint32_t both[2] = {size, std::uint32_t(soa.size())};
  std::memcpy(sizes.data(), both, 8);
  const std::string head = header(kXyz + "WIDTH 50\nHEIGHT 1\nPOINTS 50\nDATA binary_compressed\n");
  const auto c = readPcd(write(head + sizes + packed), true);
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) EXPECT_EQ(c.at(std::uint64_t(i), a), a * 1000 + i % 7);

  // The same block with a byte flipped inside a back reference, and cut.
  std::string corrupt = packed;
  corrupt[corrupt.size() / 2] = char(0xff);
  EXPECT_NE(problem(head + sizes + corrupt), "accepted");
  EXPECT_NE(problem(head + sizes + packed.substr(0, size - 3)).find("the file has"),
            std::string::npos);
}

TEST_F(Pcd, RefusesMalformedHeadersNamingTheProblem) {
  const std::string pts = "WIDTH 2\nHEIGHT 1\nPOINTS 2\n";
  EXPECT_NE(problem("").find("empty"), std::string::npos);
  EXPECT_NE(problem(header(kXyz + pts)).find("before its DATA line"), std::string::npos);
  EXPECT_NE(problem(header("FIELDS x y z\nSIZE 4 4\nTYPE F F F\n" + pts + "DATA ascii\n"))
                .find("SIZE lists 2 entries for 3 FIELDS"),
            std::string::npos);
  EXPECT_NE(problem(header("FIELDS x y\nSIZE 4 4\nTYPE F F\nCOUNT 1 1\n" + pts + "DATA ascii\n"))
                .find("no field z"),
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

TEST_F(Pcd, HeaderKeywordsComeOnceInOrderWithWholeValues) {
  const std::string data = "DATA ascii\n1 2 3\n";
  EXPECT_NE(problem("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nPOINTS 1\n" + data)
                .find("no VERSION before FIELDS"),
            std::string::npos);
  EXPECT_NE(problem(header(kXyz + "WIDTH 1\nWIDTH 1\nHEIGHT 1\nPOINTS 1\n" + data))
                .find("WIDTH is repeated or out of order"),
            std::string::npos);
  EXPECT_NE(problem(header(kXyz + "HEIGHT 1\nWIDTH 1\nPOINTS 1\n" + data)).find("no WIDTH"),
            std::string::npos);
  EXPECT_NE(problem(header(kXyz + "WIDTH 1\nHEIGHT 1\n" + data)).find("no POINTS before DATA"),
            std::string::npos);
  EXPECT_NE(problem(header(kXyz + "WIDTH 1 2\nHEIGHT 1\nPOINTS 1\n" + data))
                .find("WIDTH takes one number"),
            std::string::npos);
  EXPECT_NE(problem(header(kXyz + "WIDTH 1x\nHEIGHT 1\nPOINTS 1\n" + data))
                .find("WIDTH '1x' is not a whole number"),
            std::string::npos);
  EXPECT_NE(problem(header(kXyz + "WIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0\nPOINTS 1\n" + data))
                .find("VIEWPOINT has 6 numbers, not 7"),
            std::string::npos);
  EXPECT_NE(
      problem(header(kXyz + "WIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 inf\nPOINTS 1\n" + data))
          .find("VIEWPOINT is not finite"),
      std::string::npos);
  EXPECT_NE(problem(header(kXyz + "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii F\n1 2 3\n"))
                .find("DATA line has more than one word"),
            std::string::npos);
  EXPECT_NE(problem(header("FIELDS x y z x\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 1\nHEIGHT 1\n"
                           "POINTS 1\n" +
                           data))
                .find("field x is listed twice"),
            std::string::npos);
  EXPECT_NE(problem("# .PCD\nVERSION 0.5\n" + kXyz).find("VERSION '0.5' is not 0.7"),
            std::string::npos);
}

// Found by fuzz_pcd (tests/fuzz/corpus/fuzz_pcd/pcl-readheader-overflow.pcd):
// a VIEWPOINT with a stray byte, a DATA line with a second word and a second
// header after it. PCL's readHeader read past its buffer on it, and
// `ambler-cli info` reported points at x = 894,685,376 m.
TEST_F(Pcd, RefusesTheHeaderOnWhichPclReadPastItsBuffer) {
  std::ifstream in(
      std::filesystem::path(AMBLER_FUZZ_CORPUS_DIR) / "fuzz_pcd" / "pcl-readheader-overflow.pcd",
      std::ios::binary);
  ASSERT_TRUE(in);
  const std::string bytes(std::istreambuf_iterator<char>(in), {});
  EXPECT_NE(problem(bytes).find("VIEWPOINT '0?' is not a number"), std::string::npos)
      << problem(bytes);
}

TEST_F(Pcd, RefusesDataOfTheWrongLengthOrKind) {
  const std::string head = header(kXyz + "WIDTH 4\nHEIGHT 1\nPOINTS 4\n");
  EXPECT_EQ(problem(head + "DATA binary\n" + binaryPoints(4)), "accepted");
  EXPECT_NE(problem(head + "DATA binary\n" + binaryPoints(3)).find("truncated: 4 points need 48"),
            std::string::npos);
  EXPECT_NE(problem(head + "DATA binary\n" + binaryPoints(4) + "x").find("too long"),
            std::string::npos);
  EXPECT_NE(problem(head + "DATA binary_compressed\n" + "\x05").find("no compressed block"),
            std::string::npos);
  std::string sizes(8, '\0');
  sizes[0] = 100, sizes[4] = 48;
  EXPECT_NE(problem(head + "DATA binary_compressed\n" + sizes + "abcd").find("the file has 4"),
            std::string::npos);
  sizes[0] = 4, sizes[4] = 40;
  EXPECT_NE(problem(head + "DATA binary_compressed\n" + sizes + "abcd").find("unpacks to 40"),
            std::string::npos);
  // 48 bytes cannot come out of 0 bytes of LZF.
  sizes[0] = 0, sizes[4] = 48;
  EXPECT_NE(problem(head + "DATA binary_compressed\n" + sizes), "accepted");

  EXPECT_NE(problem(head + "DATA ascii\n1 2 3\n4 5 6\n7 8 9\n").find("truncated: 3 of 4"),
            std::string::npos);
  EXPECT_NE(
      problem(head + "DATA ascii\n1 2 3\n4 5\n7 8 9\n1 1 1\n").find("point 1 has 2 values, not 3"),
      std::string::npos);
  EXPECT_NE(
      problem(head + "DATA ascii\n1 2 3\n4 5 6\n7 8 9\n1 1 1\n2 2 2\n").find("more than 4 points"),
      std::string::npos);
  EXPECT_NE(problem(head + "DATA ascii\n1 2 3\n4 5 six\n7 8 9\n1 1 1\n")
                .find("point 1 z 'six' is not a number"),
            std::string::npos);
  EXPECT_NE(problem(header("FIELDS x y z i\nSIZE 4 4 4 1\nTYPE F F F U\nWIDTH 1\nHEIGHT 1\n"
                           "POINTS 1\nDATA ascii\n1 2 3 256\n"))
                .find("point 0 i 256 is not an unsigned integer of 1 bytes"),
            std::string::npos);
}

}  // namespace
}  // namespace ambler::io
