#include "link/Signing.h"

#include <gtest/gtest.h>

#include <fstream>

#include "TempDir.h"
#include "io/FormatError.h"
#include "link/Codec.h"

namespace ambler::link {
namespace {

OperatorKey key(const std::string& id, std::uint8_t fill) {
  return {id, std::vector<std::uint8_t>(32, fill)};
}

Command bodyMove(std::uint32_t rover = 1) {
  Command c;
  c.rover_id = rover;
  c.body = BodyMove{0.0, 0.5, 0.0, 0.0};
  return c;
}

// Commands signed at t = 100 s, valid for 10 s.
SignerOptions at100() {
  return {.validity_s = 10.0, .clock = [] { return 100.0; }};
}
constexpr double kArrival = 100.2;

// RFC 4231 test case 2: key "Jefe", data "what do ya want for nothing?".
TEST(Signing, HmacSha256MatchesRfc4231) {
  const std::string k = "Jefe", d = "what do ya want for nothing?";
  const Hmac mac = hmacSha256({reinterpret_cast<const std::uint8_t*>(k.data()), k.size()},
                              {reinterpret_cast<const std::uint8_t*>(d.data()), d.size()});
  const std::uint8_t expected[32] = {0x5b, 0xdc, 0xc1, 0x46, 0xbf, 0x60, 0x75, 0x4e,
                                     0x6a, 0x04, 0x24, 0x26, 0x08, 0x95, 0x75, 0xc7,
                                     0x5a, 0x00, 0x3f, 0x08, 0x9d, 0x27, 0x39, 0x83,
                                     0x9d, 0xec, 0x58, 0xb9, 0x64, 0xec, 0x38, 0x43};
  EXPECT_TRUE(std::equal(mac.begin(), mac.end(), expected));
}

TEST(Signing, ASignedCommandIsAcceptedOnceAndInOrder) {
  CommandSigner alice(key("alice", 1), 1, at100());
  CommandVerifier rover(1, {key("alice", 1), key("bob", 2)});
  Command first = bodyMove(), second = bodyMove();
  alice.sign(first);
  alice.sign(second);
  EXPECT_EQ(first.sequence, 1u);
  EXPECT_EQ(second.sequence, 2u);
  EXPECT_FALSE(rover.check(first, kArrival).refused());
  // Through the wire form as well.
  EXPECT_FALSE(rover.check(decodeCommand(encode(second)), kArrival).refused());
  EXPECT_NE(rover.check(second, kArrival).why().find("replayed command: sequence 2"),
            std::string::npos);
  EXPECT_NE(rover.check(first, kArrival).why().find("out of order: sequence 1 after 2"),
            std::string::npos);
}

TEST(Signing, EveryKindOfBadCommandIsRefusedWithItsReason) {
  CommandVerifier rover(1, {key("alice", 1)});
  Command c = bodyMove();
  EXPECT_EQ(rover.check(c, kArrival).why(), "unsigned command");

  CommandSigner mallory(key("mallory", 9), 1, at100());
  mallory.sign(c);
  EXPECT_EQ(rover.check(c, kArrival).why(), "unknown operator \"mallory\"");

  CommandSigner forged(key("alice", 9), 1, at100());  // alice's name, the wrong key
  c = bodyMove();
  forged.sign(c);
  EXPECT_EQ(rover.check(c, kArrival).why(), "bad signature for operator \"alice\"");

  CommandSigner alice(key("alice", 1), 1, at100());
  c = bodyMove();
  alice.sign(c);
  std::get<BodyMove>(c.body).y_m = 3.0;  // tampered with after signing
  EXPECT_EQ(rover.check(c, kArrival).why(), "bad signature for operator \"alice\"");

  c = bodyMove(2);
  alice.sign(c);
  EXPECT_EQ(rover.check(c, kArrival).why(), "addressed to rover 2, this is rover 1");

  CommandSigner zero(key("alice", 1), 0, at100());
  c = bodyMove();
  zero.sign(c);
  EXPECT_EQ(rover.check(c, kArrival).why(), "sequence 0 (sequences start at 1)");
}

TEST(Signing, ACommandIsRefusedOnBoardOnceItsValidityWindowHasClosed) {
  CommandSigner alice(key("alice", 1), 1, at100());
  CommandVerifier rover(1, {key("alice", 1)});
  Command in_time = bodyMove(), late = bodyMove(), hold;
  hold.rover_id = 1, hold.body = Hold{};
  alice.sign(in_time), alice.sign(late), alice.sign(hold);
  EXPECT_EQ(in_time.valid_until_s, 110.0);
  EXPECT_FALSE(rover.check(in_time, 109.9).refused());
  EXPECT_EQ(rover.check(late, 112.5).why(),
            "arrived 2.50 s after its validity window closed (signed 12.5 s ago, valid for "
            "10.0 s)");
  // Stopping late is still better than not stopping.
  EXPECT_FALSE(rover.check(hold, 112.5).refused());

  Command no_window = bodyMove(), too_long = bodyMove();
  alice.sign(no_window);
  no_window.valid_until_s = 0.0;
  no_window.hmac = hmacSha256(key("alice", 1).key, signedContent(no_window));
  EXPECT_EQ(rover.check(no_window, kArrival).why(), "no validity window");
  CommandSigner patient(key("alice", 1), 1, {.validity_s = 3600.0, .clock = [] { return 100.0; }});
  patient.sign(too_long);
  EXPECT_EQ(rover.check(too_long, kArrival).why(),
            "validity window of 3600.0 s (0-600.0 s accepted)");
}

// Sequences live in the rover's memory only; what a restart forgets, the
// start time covers: a command signed before it is refused.
TEST(Signing, ACommandRecordedBeforeTheRoverRestartsIsRefusedAfterIt) {
  CommandSigner alice(key("alice", 1), 1, at100());
  Command c = bodyMove();
  alice.sign(c);
  CommandVerifier before(1, {key("alice", 1)});
  before.startedAt(50.0);
  EXPECT_FALSE(before.check(c, kArrival).refused());
  EXPECT_TRUE(before.check(c, kArrival + 1).refused());

  CommandVerifier after(1, {key("alice", 1)});  // restarted at t = 101 s
  after.startedAt(101.0);
  EXPECT_EQ(after.check(c, 101.5).why(),
            "signed 1.00 s before this rover's link started (a command from before a restart)");
}

// One operator's key in two consoles (the GUI and ambler-cli drive): each
// console numbers its own commands, and neither breaks the other's order.
TEST(Signing, TwoConsolesWithTheSameKeyKeepTheirOwnOrder) {
  CommandSigner gui(key("alice", 1), 1000, at100()), drive(key("alice", 1), 5, at100());
  EXPECT_NE(gui.consoleId(), drive.consoleId());
  CommandVerifier rover(1, {key("alice", 1)});
  for (int i = 0; i < 3; ++i) {
    Command a = bodyMove(), b = bodyMove();
    gui.sign(a), drive.sign(b);
    EXPECT_FALSE(rover.check(a, kArrival).refused());
    EXPECT_FALSE(rover.check(b, kArrival).refused());
  }
}

TEST(Signing, KeyFilesAreReadAndBadOnesNamed) {
  const auto dir = std::filesystem::temp_directory_path() / "ambler_signing_test";
  std::filesystem::create_directories(dir);
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return dir / name;
  };
  const auto good = write(
      "alice.json", R"({"operator": "alice", "key_hex": "000102030405060708090a0b0c0d0e0f10"})");
  const OperatorKey k = readOperatorKey(good);
  EXPECT_EQ(k.operator_id, "alice");
  ASSERT_EQ(k.key.size(), 17u);
  EXPECT_EQ(k.key[16], 0x10);
  const auto keys = write("keys.json", R"({"operators": [
      {"operator": "alice", "key_hex": "000102030405060708090a0b0c0d0e0f"},
      {"operator": "bob", "key_hex": "ffeeddccbbaa99887766554433221100"}]})");
  EXPECT_EQ(readOperatorKeys(keys).size(), 2u);

  auto expectProblem = [&](const std::string& text, const std::string& words) {
    const auto path = write("bad.json", text);
    try {
      readOperatorKey(path);
      FAIL() << text;
    } catch (const io::FormatError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
    }
  };
  expectProblem(R"({"operator": "a", "key_hex": "0011"})", "at least 16 are needed");
  expectProblem(R"({"operator": "a", "key_hex": "001"})", "odd number");
  expectProblem(R"({"operator": "a", "key_hex": "zz0102030405060708090a0b0c0d0e0f"})",
                "not hexadecimal");
  expectProblem(R"({"key_hex": "000102030405060708090a0b0c0d0e0f"})", "operator");
  std::filesystem::remove_all(dir);
}

TEST(Signing, NewKeysAreRandomPrivateAndNeverReplaced) {
  const TempDir dir;
  const auto alice = newOperatorKey("alice");
  EXPECT_EQ(alice.key.size(), 32u);
  EXPECT_NE(alice.key, newOperatorKey("alice").key);
  EXPECT_EQ(keyHex(alice).size(), 64u);
  writeOperatorKey(dir / "alice.key", alice);
  const auto back = readOperatorKey(dir / "alice.key");
  EXPECT_EQ(back.operator_id, "alice");
  EXPECT_EQ(back.key, alice.key);
  namespace fs = std::filesystem;
  EXPECT_EQ(fs::status(dir / "alice.key").permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write);
  // A second key for the same file would lock its operator out.
  EXPECT_THROW(writeOperatorKey(dir / "alice.key", newOperatorKey("alice")), std::runtime_error);
  EXPECT_EQ(readOperatorKey(dir / "alice.key").key, alice.key);
  EXPECT_THROW(newOperatorKey(""), std::invalid_argument);
  EXPECT_THROW(newOperatorKey("al ice"), std::invalid_argument);
  EXPECT_THROW(newOperatorKey(std::string(257, 'a')), std::invalid_argument);
}

}  // namespace
}  // namespace ambler::link
