// The range-image reader (formats.md, "Range image") on arbitrary files:
// the input is a 2-byte little-endian length, that many bytes of JSON
// sidecar, then the TIFF. Malformed, truncated or inconsistent files must
// end in an io::FormatError naming the problem, never a crash.
#include "FuzzSupport.h"
#include "io/FormatError.h"
#include "sensor/RangeImageFile.h"

using namespace ambler;

namespace {

fuzz::Bytes pack(const fuzz::Bytes& json, const fuzz::Bytes& tiff) {
  fuzz::Bytes out{std::uint8_t(json.size() & 0xff), std::uint8_t(json.size() >> 8)};
  out.insert(out.end(), json.begin(), json.end());
  out.insert(out.end(), tiff.begin(), tiff.end());
  return out;
}

std::vector<fuzz::Bytes> seeds() {
  sensor::RangeImage image;
  image.geometry = {4, 5, -0.5, 0.01, -0.2, 0.01};
  image.range_sigma_k = 2e-4;
  image.range.assign(20, 7.5f);
  image.range[3] = NAN;  // no return
  std::vector<fuzz::Bytes> out;
  for (const bool reflectance : {false, true}) {
    if (reflectance) image.reflectance.assign(20, 0.5f);
    const auto tif = fuzz::scratchDir() / "seed.tif";
    sensor::writeRangeImage(image, tif);
    out.push_back(pack(fuzz::readBytes(sensor::sidecarPath(tif)), fuzz::readBytes(tif)));
  }
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  fuzz::seedCorpus(*argc, *argv, seeds);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::size_t json_size = std::min<std::size_t>(data[0] | (data[1] << 8), size - 2);
  const auto tif = fuzz::writeScratch("scan.tif", data + 2 + json_size, size - 2 - json_size);
  fuzz::writeScratch("scan.json", data + 2, json_size);
  fuzz::refusalOnly<io::FormatError>([&] {
    const auto image = sensor::readRangeImage(tif);
    if (image.range.size() != std::size_t(image.rows()) * std::size_t(image.cols())) std::abort();
  });
  return 0;
}
