// The link's byte decoder (formats.md, "Link messages") on arbitrary bytes:
// it must refuse with a DecodeError or accept, never crash; what it accepts
// must encode to bytes that decode to the same encoding.
#include "FuzzSupport.h"
#include "link/Codec.h"

using namespace ambler;

namespace {

template <typename Decode>
void roundTrip(std::span<const std::uint8_t> bytes, Decode decode) {
  fuzz::refusalOnly<link::DecodeError>([&] {
    const auto once = link::encode(decode(bytes));
    if (link::encode(decode(once)) != once) std::abort();
  });
}

std::vector<fuzz::Bytes> seeds() {
  link::Telemetry heartbeat{1, 2.5, link::Heartbeat{7, true, "Hold from alice", {}, {}}};
  link::Telemetry body{1, 3.0, link::BodyState{1.0, 2.0, 2.4, 0.1, true}};
  sensor::RangeImage image;
  image.geometry.rows = 2, image.geometry.cols = 3;
  image.geometry.phi_step = image.geometry.theta_step = 0.01;
  image.range.assign(6, 5.0f);
  link::Telemetry scan{1, 4.0, image};
  link::Command move;
  move.rover_id = 1, move.operator_id = "alice", move.sequence = 3;
  move.body = link::BodyMove{0.0, 0.5, 0.0, 0.0};
  link::Command leg = move;
  leg.body = link::LegMove{2, {{0.1, 2.0, 1.0}, {0.2, 2.1, 0.9}}};
  return {link::encode(heartbeat), link::encode(body), link::encode(scan), link::encode(move),
          link::encode(leg)};
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  fuzz::seedCorpus(*argc, *argv, seeds);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  roundTrip(bytes, [](auto b) { return link::decodeTelemetry(b); });
  roundTrip(bytes, [](auto b) { return link::decodeCommand(b); });
  return 0;
}
