// The JSON readers an operator hands files to: operator keys (console and
// rover side), the rover configuration and the footfall configuration, on
// arbitrary bytes. Anything they cannot use must end in an io::FormatError
// naming the file and the field, never a crash or a stray exception.
#include "FuzzSupport.h"
#include "footfall/FootfallConfig.h"
#include "gait/RoverConfig.h"
#include "io/FormatError.h"
#include "link/Signing.h"

using namespace ambler;

namespace {

std::vector<fuzz::Bytes> seeds() {
  auto text = [](const std::string& s) { return fuzz::Bytes(s.begin(), s.end()); };
  std::vector<fuzz::Bytes> out{
      text(R"({"operator": "alice", "key_hex": "000102030405060708090a0b0c0d0e0f"})"),
      text(
          R"({"operators": [{"operator": "bob", "key_hex": "ffeeddccbbaa99887766554433221100"}]})")};
  for (const char* config : {"config/rover.json", "config/footfall.json"})
    out.push_back(fuzz::readBytes(std::filesystem::path(AMBLER_SOURCE_DATA_DIR) / config));
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  fuzz::seedCorpus(*argc, *argv, seeds);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = fuzz::writeScratch("config.json", data, size);
  fuzz::refusalOnly<io::FormatError>([&] { link::readOperatorKey(path); });
  fuzz::refusalOnly<io::FormatError>([&] { link::readOperatorKeys(path); });
  fuzz::refusalOnly<io::FormatError>([&] { gait::readRoverConfig(path); });
  fuzz::refusalOnly<io::FormatError>([&] { footfall::readFootfallConfig(path); });
  return 0;
}
