#include "io/Tiff.h"

#include <tiffio.h>

#include <cstdarg>
#include <cstdio>
#include <fstream>
#include <memory>
#include <mutex>
#include <string>

#include "io/ReplaceFile.h"

namespace ambler::io {

namespace {

// libtiff reports through a process-wide handler; keep the last message per
// thread so it can be put into the exception of the call that failed.
thread_local std::string t_last_tiff_error;

void captureTiffError(const char* module, const char* fmt, va_list args) {
  char buffer[512];
  std::vsnprintf(buffer, sizeof buffer, fmt, args);
  t_last_tiff_error = module ? std::string(module) + ": " + buffer : std::string(buffer);
}

void installHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    TIFFSetErrorHandler(captureTiffError);
    TIFFSetWarningHandler(nullptr);
  });
}

struct TiffCloser {
  void operator()(TIFF* t) const { TIFFClose(t); }
};
using TiffPtr = std::unique_ptr<TIFF, TiffCloser>;

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what) {
  throw FormatError("TIFF '" + path.string() + "': " + what);
}

std::string lastError() {
  return t_last_tiff_error.empty() ? std::string("unknown libtiff error") : t_last_tiff_error;
}

bool hasTiffSignature(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[4] = {};
  in.read(magic, 4);
  const std::string m(magic, 4);
  return in && (m == std::string("II*\0", 4) || m == std::string("MM\0*", 4));
}

TiffPtr openForReading(const std::filesystem::path& path) {
  installHandlers();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail(path, "file does not exist");
  if (!std::filesystem::is_regular_file(path, ec)) fail(path, "not a regular file");
  t_last_tiff_error.clear();
  TiffPtr tif(TIFFOpen(path.c_str(), "r"));
  if (!tif) {
    // libtiff writes the directory last, so a cut-off file usually still
    // starts with the TIFF signature but has lost its directory.
    fail(path, (hasTiffSignature(path) ? "truncated or corrupt TIFF (" : "not a TIFF file (") +
                   lastError() + ")");
  }
  return tif;
}

template <typename T>
Image<T> readTiff(const std::filesystem::path& path, uint16_t bits, uint16_t format,
                  const char* type_name) {
  TiffPtr tif = openForReading(path);
  uint32_t width = 0, height = 0;
  uint16_t samples = 1, bits_per_sample = 1, sample_format = SAMPLEFORMAT_UINT;
  if (!TIFFGetField(tif.get(), TIFFTAG_IMAGEWIDTH, &width) ||
      !TIFFGetField(tif.get(), TIFFTAG_IMAGELENGTH, &height))
    fail(path, "missing image width or length tag");
  TIFFGetFieldDefaulted(tif.get(), TIFFTAG_SAMPLESPERPIXEL, &samples);
  TIFFGetFieldDefaulted(tif.get(), TIFFTAG_BITSPERSAMPLE, &bits_per_sample);
  TIFFGetFieldDefaulted(tif.get(), TIFFTAG_SAMPLEFORMAT, &sample_format);

  if (width == 0 || height == 0) fail(path, "image has zero width or height");
  if (long(width) * long(height) > kMaxTiffPixels)
    fail(path, "image of " + std::to_string(width) + "x" + std::to_string(height) +
                   " pixels is larger than accepted");
  if (samples != 1)
    fail(path, "expected a single channel, found " + std::to_string(samples) + " samples/pixel");
  if (bits_per_sample != bits || sample_format != format)
    fail(path, std::string("expected ") + type_name + " samples, found " +
                   std::to_string(bits_per_sample) + "-bit " +
                   (sample_format == SAMPLEFORMAT_IEEEFP ? "float" : "integer"));
  if (TIFFIsTiled(tif.get())) fail(path, "tiled TIFFs are not supported; write it in strips");
  if (TIFFScanlineSize(tif.get()) != tmsize_t(width * sizeof(T)))
    fail(path, "unexpected scanline size");

  Image<T> image{int(height), int(width)};
  for (uint32_t r = 0; r < height; ++r) {
    if (TIFFReadScanline(tif.get(), &image(int(r), 0), r) < 0)
      fail(path, "truncated or corrupt at row " + std::to_string(r) + " (" + lastError() + ")");
  }
  return image;
}

template <typename T>
void writeTiffImpl(const std::filesystem::path& path, const Image<T>& image, uint16_t format) {
  installHandlers();
  if (image.rows <= 0 || image.cols <= 0 ||
      image.pixels.size() != std::size_t(image.rows) * image.cols)
    fail(path, "refusing to write an image whose size does not match its pixel count");
  writeThenReplace(path, [&](const std::filesystem::path& partial) {
    t_last_tiff_error.clear();
    TiffPtr tif(TIFFOpen(partial.c_str(), "w"));
    if (!tif) fail(path, "cannot create file (" + lastError() + ")");
    TIFFSetField(tif.get(), TIFFTAG_IMAGEWIDTH, uint32_t(image.cols));
    TIFFSetField(tif.get(), TIFFTAG_IMAGELENGTH, uint32_t(image.rows));
    TIFFSetField(tif.get(), TIFFTAG_SAMPLESPERPIXEL, uint16_t(1));
    TIFFSetField(tif.get(), TIFFTAG_BITSPERSAMPLE, uint16_t(sizeof(T) * 8));
    TIFFSetField(tif.get(), TIFFTAG_SAMPLEFORMAT, format);
    TIFFSetField(tif.get(), TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
    TIFFSetField(tif.get(), TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(tif.get(), TIFFTAG_COMPRESSION, COMPRESSION_NONE);
    TIFFSetField(tif.get(), TIFFTAG_ROWSPERSTRIP, TIFFDefaultStripSize(tif.get(), 0));
    for (int r = 0; r < image.rows; ++r) {
      // libtiff's API takes a non-const buffer but does not modify it.
      auto* row = const_cast<T*>(&image(r, 0));
      if (TIFFWriteScanline(tif.get(), row, uint32_t(r)) < 0)
        fail(path, "write failed at row " + std::to_string(r) + " (" + lastError() + ")");
    }
  });
}

}  // namespace

FloatImage readFloatTiff(const std::filesystem::path& path) {
  return readTiff<float>(path, 32, SAMPLEFORMAT_IEEEFP, "32-bit float");
}

ByteImage readByteTiff(const std::filesystem::path& path) {
  return readTiff<unsigned char>(path, 8, SAMPLEFORMAT_UINT, "8-bit unsigned");
}

void writeTiff(const std::filesystem::path& path, const FloatImage& image) {
  writeTiffImpl(path, image, SAMPLEFORMAT_IEEEFP);
}

void writeTiff(const std::filesystem::path& path, const ByteImage& image) {
  writeTiffImpl(path, image, SAMPLEFORMAT_UINT);
}

}  // namespace ambler::io
