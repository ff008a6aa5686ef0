#include "link/Codec.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ambler::link {
namespace {

Command legMove() {
  Command c;
  c.rover_id = 3;
  c.operator_id = "alice";
  c.sequence = 42;
  c.time_s = 1234.5;
  c.body = LegMove{4, {{0.1, 1.5, 2.0}, {0.2, 1.6, 1.4}, {0.3, 1.7, 2.1}}};
  c.hmac = Hmac{};
  (*c.hmac)[0] = 0xAB, (*c.hmac)[31] = 0xCD;
  return c;
}

sensor::RangeImage smallImage() {
  sensor::RangeImage image;
  image.geometry = sensor::ScanGeometry::symmetric(3, 4, 0.5, 0.8);
  image.sensor_to_world.translation() = Eigen::Vector3d(1, 2, 5);
  image.range_sigma_k = 2e-4;
  image.range = {1, 2, 3, 4, 5, 6, NAN, 8, 9, 10, 11, 0};
  return image;
}

TEST(Codec, CommandsSurviveTheRoundTripExactly) {
  const Command c = legMove();
  const Command d = decodeCommand(encode(c));
  EXPECT_EQ(d.rover_id, 3u);
  EXPECT_EQ(d.operator_id, "alice");
  EXPECT_EQ(d.sequence, 42u);
  EXPECT_EQ(d.time_s, 1234.5);
  ASSERT_TRUE(d.hmac.has_value());
  EXPECT_EQ(*d.hmac, *c.hmac);
  const auto& move = std::get<LegMove>(d.body);
  EXPECT_EQ(move.leg, 4);
  ASSERT_EQ(move.waypoints.size(), 3u);
  EXPECT_EQ(move.waypoints[1].extension_m, 1.6);
  EXPECT_EQ(typeName(d.body), "LegMove");
  // The signed content is the encoding less the signature.
  EXPECT_EQ(encode(c).size(), signedContent(c).size() + 1 + 32);
}

TEST(Codec, TelemetryWithARangeImageSurvivesTheRoundTrip) {
  Telemetry t{7, 99.25, smallImage()};
  const Telemetry u = decodeTelemetry(encode(t));
  EXPECT_EQ(u.rover_id, 7u);
  EXPECT_EQ(u.time_s, 99.25);
  const auto& image = std::get<sensor::RangeImage>(u.body);
  EXPECT_EQ(image.rows(), 3);
  EXPECT_EQ(image.cols(), 4);
  EXPECT_EQ(image.at(2, 3), 0.0f);
  EXPECT_TRUE(std::isnan(image.at(1, 2)));
  EXPECT_EQ(image.sensor_to_world.translation().z(), 5.0);
  EXPECT_EQ(typeName(u.body), "RangeImage");
}

TEST(Codec, HoldsHeartbeatsAndLegStatesSurviveTheRoundTrip) {
  const Telemetry t{1, 5.0, Heartbeat{9, true, "Hold from alice", "alice@01", "bob@02"}};
  const auto h = std::get<Heartbeat>(decodeTelemetry(encode(t)).body);
  EXPECT_EQ(h.count, 9u);
  EXPECT_TRUE(h.holding);
  EXPECT_EQ(h.hold_reason, "Hold from alice");
  EXPECT_EQ(h.authority, "alice@01");
  EXPECT_EQ(h.authority_request, "bob@02");
  const auto ack = std::get<CommandAck>(
      decodeTelemetry(encode(Telemetry{1, 5.0, CommandAck{"bob", 77, 12, false, "late"}})).body);
  EXPECT_EQ(ack.console_id, 77u);
  EXPECT_EQ(ack.sequence, 12u);
  const auto leg = std::get<LegState>(
      decodeTelemetry(encode(Telemetry{1, 5.0, LegState{4, {0.1, 2.0, 1.9}, true, 5230.5}})).body);
  EXPECT_EQ(leg.leg, 4);
  EXPECT_TRUE(leg.contact);
  EXPECT_EQ(leg.force_n, 5230.5);
  for (const CommandBody& body : std::vector<CommandBody>{GroundHeartbeat{}, Resume{}, Hold{},
                                                          RequestAuthority{}, HandOver{"bob@02"}}) {
    Command c = legMove();
    c.body = body;
    c.console_id = 0xfeedu, c.valid_until_s = 12.5;
    const Command back = decodeCommand(encode(c));
    EXPECT_EQ(back.body.index(), body.index()) << typeName(body);
    EXPECT_EQ(back.console_id, 0xfeedu);
    EXPECT_EQ(back.valid_until_s, 12.5);
  }
  Command c = legMove();
  c.body = HandOver{"bob@02"};
  EXPECT_EQ(std::get<HandOver>(decodeCommand(encode(c)).body).console, "bob@02");
}

// Every prefix of a valid message is refused with a message that says it is
// truncated; nothing reads past the end.
TEST(Codec, TruncatedMessagesAreRefusedAtEveryLength) {
  for (const Bytes& full : {encode(legMove()), encode(Telemetry{1, 2.0, smallImage()})}) {
    for (std::size_t n = 0; n < full.size(); ++n) {
      const std::span<const std::uint8_t> prefix(full.data(), n);
      try {
        if (full[5] == 1)
          decodeCommand(prefix);
        else
          decodeTelemetry(prefix);
        FAIL() << "a prefix of " << n << " bytes decoded";
      } catch (const DecodeError& e) {
        EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
      }
    }
  }
}

void expectRefused(const Bytes& bytes, const std::string& words) {
  try {
    decodeCommand(bytes);
    FAIL() << "decoded; expected: " << words;
  } catch (const DecodeError& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

// Mission logs written before console ids and validity windows hold
// version 2 messages; they still read, with neither.
TEST(Codec, Version2MessagesFromOlderMissionLogsStillDecode) {
  auto put = [](Bytes& b, const auto& v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    b.insert(b.end(), p, p + sizeof v);
  };
  Bytes hold = {'A', 'M', 'B', 'L', 2, 1, 4};  // command kind, type Hold
  put(hold, std::uint32_t(7));
  put(hold, std::uint16_t(5));
  for (char ch : std::string("alice")) hold.push_back(std::uint8_t(ch));
  put(hold, std::uint64_t(42));
  put(hold, 1.5);
  hold.push_back(0);  // unsigned
  const Command c = decodeCommand(hold);
  EXPECT_EQ(c.rover_id, 7u);
  EXPECT_EQ(c.operator_id, "alice");
  EXPECT_EQ(c.sequence, 42u);
  EXPECT_EQ(c.console_id, 0u);
  EXPECT_EQ(c.valid_until_s, 0.0);
  EXPECT_TRUE(std::holds_alternative<Hold>(c.body));

  Bytes beat = {'A', 'M', 'B', 'L', 2, 0, 0};  // telemetry kind, type Heartbeat
  put(beat, std::uint32_t(7));
  put(beat, 2.0);
  put(beat, std::uint64_t(3));
  beat.push_back(1);
  put(beat, std::uint16_t(4));
  for (char ch : std::string("Hold")) beat.push_back(std::uint8_t(ch));
  const auto h = std::get<Heartbeat>(decodeTelemetry(beat).body);
  EXPECT_TRUE(h.holding);
  EXPECT_EQ(h.hold_reason, "Hold");
  EXPECT_TRUE(h.authority.empty());
}

TEST(Codec, MalformedCommandsAreRefusedWithTheProblemNamed) {
  const Bytes good = encode(legMove());
  Bytes b = good;
  b[0] = 'X';
  expectRefused(b, "bad magic");
  b = good, b[4] = 9;
  expectRefused(b, "unsupported version 9");
  b = good, b[5] = 0;
  expectRefused(b, "expected a command");
  b = good, b[6] = 200;
  expectRefused(b, "unknown message type 200");
  b = good, b.push_back(0);
  expectRefused(b, "1 bytes left over");
  // The leg index sits right after the header, rover id, operator id,
  // console id, sequence, time and validity.
  const std::size_t leg_at = 7 + 4 + 2 + 5 + 8 + 8 + 8 + 8;
  b = good, b[leg_at] = 6;
  expectRefused(b, "leg 6 out of range");
  Command c = legMove();
  std::get<LegMove>(c.body).waypoints[0].vertical_m = NAN;
  expectRefused(encode(c), "joint vertical is not a finite number");
  std::get<LegMove>(c.body).waypoints.clear();
  expectRefused(encode(c), "0 waypoints");
  c = legMove();
  c.body = BodyMove{INFINITY, 0, 0, 0};
  expectRefused(encode(c), "body move x is not a finite number");
  // A telemetry message is not a command.
  expectRefused(encode(Telemetry{1, 2.0, Heartbeat{5, false, {}, {}, {}}}), "expected a command");
}

TEST(Codec, ARangeImageWhoseSizeDisagreesIsRefused) {
  Bytes b = encode(Telemetry{1, 2.0, smallImage()});
  // rows (u32) right after header (7), rover id (4) and time (8).
  b[19] = 5;
  try {
    decodeTelemetry(b);
    FAIL();
  } catch (const DecodeError& e) {
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
  b = encode(Telemetry{1, 2.0, smallImage()});
  b[19] = 0;
  try {
    decodeTelemetry(b);
    FAIL();
  } catch (const DecodeError& e) {
    EXPECT_NE(std::string(e.what()).find("0 x 4 pixels"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ambler::link
