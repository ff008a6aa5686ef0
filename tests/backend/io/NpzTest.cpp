// NumPy archives: arrays written here with minizip's zip API, in the
// layout numpy.savez_compressed writes, read back; broken ones refused
// with the problem named.
#include "io/Npz.h"

#include <gtest/gtest.h>
#include <minizip/zip.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "TempDir.h"

namespace ambler::io {
namespace {

// A .npy 1.0 file: magic, version, header padded to 64 bytes, data.
std::string npy(const std::string& descr, const std::string& shape, const void* data,
                std::size_t bytes) {
  std::string header =
      "{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + shape + ", }";
  header.append(64 - (10 + header.size() + 1) % 64, ' ');
  header += '\n';
  std::string out = "\x93NUMPY";
  out += char(1), out += char(0);
  out += char(header.size() & 0xff), out += char(header.size() >> 8);
  out += header;
  out.append(static_cast<const char*>(data), bytes);
  return out;
}

void writeZip(const std::filesystem::path& path,
              const std::vector<std::pair<std::string, std::string>>& entries) {
  zipFile zip = zipOpen64(path.string().c_str(), APPEND_STATUS_CREATE);
  ASSERT_NE(zip, nullptr);
  for (const auto& [name, bytes] : entries) {
    ASSERT_EQ(zipOpenNewFileInZip64(zip, name.c_str(), nullptr, nullptr, 0, nullptr, 0, nullptr,
                                    Z_DEFLATED, Z_DEFAULT_COMPRESSION, 0),
              ZIP_OK);
    ASSERT_EQ(zipWriteInFileInZip(zip, bytes.data(), unsigned(bytes.size())), ZIP_OK);
    zipCloseFileInZip(zip);
  }
  zipClose(zip, nullptr);
}

std::string errorOf(const std::filesystem::path& path) {
  try {
    readNpz(path);
  } catch (const FormatError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Npz, ReadsIntegerGridsAndFloatScalarsAsNumPyWritesThem) {
  TempDir dir;
  const std::int16_t grid[6] = {-3, 0, 7, 1200, -32768, 32767};
  const double scalar = -84.41375;
  const float row[3] = {0.5f, 1.5f, -2.25f};
  writeZip(dir / "a.npz", {{"elevation.npy", npy("<i2", "(2, 3)", grid, sizeof grid)},
                           {"xmin.npy", npy("<f8", "()", &scalar, sizeof scalar)},
                           {"row.npy", npy("<f4", "(3,)", row, sizeof row)}});
  const auto arrays = readNpz(dir / "a.npz");
  ASSERT_EQ(arrays.size(), 3u);
  const auto& e = arrays.at("elevation");
  EXPECT_EQ(e.shape, (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(e.values, (std::vector<double>{-3, 0, 7, 1200, -32768, 32767}));
  EXPECT_TRUE(arrays.at("xmin").shape.empty());
  EXPECT_EQ(arrays.at("xmin").values, std::vector<double>{scalar});
  EXPECT_EQ(arrays.at("row").values, (std::vector<double>{0.5, 1.5, -2.25}));
}

TEST(Npz, BrokenArchivesAreRefusedWithTheProblemNamed) {
  TempDir dir;
  EXPECT_NE(errorOf(dir / "missing.npz").find("no such file"), std::string::npos);
  { std::ofstream(dir / "text.npz") << "not a zip"; }
  EXPECT_NE(errorOf(dir / "text.npz").find("not a zip archive"), std::string::npos);
  const std::int16_t grid[6] = {};
  // Six values announced, four present.
  writeZip(dir / "short.npz", {{"z.npy", npy("<i2", "(2, 3)", grid, 8)}});
  const auto short_error = errorOf(dir / "short.npz");
  EXPECT_NE(short_error.find("entry z.npy: truncated data"), std::string::npos) << short_error;
  writeZip(dir / "complex.npz", {{"c.npy", npy("<c16", "(1,)", grid, 12)}});
  EXPECT_NE(errorOf(dir / "complex.npz").find("unsupported element type"), std::string::npos);
  writeZip(dir / "big.npz", {{"b.npy", npy(">i4", "(1,)", grid, 4)}});
  EXPECT_NE(errorOf(dir / "big.npz").find("big-endian"), std::string::npos);
  writeZip(dir / "junk.npz", {{"j.npy", "hello"}});
  EXPECT_NE(errorOf(dir / "junk.npz").find("not a NumPy array"), std::string::npos);
}

}  // namespace
}  // namespace ambler::io
