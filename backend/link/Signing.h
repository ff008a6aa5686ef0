#pragma once

// Command authentication: HMAC-SHA256 (OpenSSL) over a command's content
// with a key shared in advance between one operator and the rover, plus a
// sequence number per console and a validity window so that a recorded
// command cannot be played again. A console without a key can watch but
// never command.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/Refusal.h"
#include "link/Messages.h"

namespace ambler::link {

struct OperatorKey {
  std::string operator_id;
  std::vector<std::uint8_t> key;  // at least kMinKeyBytes
};

inline constexpr std::size_t kMinKeyBytes = 16;

// {"operator": "alice", "key_hex": "<at least 32 hex digits>"}; throws
// io::FormatError naming the file and the problem.
OperatorKey readOperatorKey(const std::filesystem::path& path);
// The rover's side: {"operators": [{"operator": ..., "key_hex": ...}, ...]}.
std::vector<OperatorKey> readOperatorKeys(const std::filesystem::path& path);

// A new key of 32 random bytes (OpenSSL's generator) for `operator_id`
// (1-256 bytes of printable ASCII); throws std::invalid_argument otherwise.
OperatorKey newOperatorKey(const std::string& operator_id);
// Writes a console's key file, readable by its owner only; never replaces
// an existing file (throws std::runtime_error naming it).
void writeOperatorKey(const std::filesystem::path& path, const OperatorKey& key);
// The key as lowercase hex digits, as key files hold it.
std::string keyHex(const OperatorKey& key);

Hmac hmacSha256(std::span<const std::uint8_t> key, std::span<const std::uint8_t> data);

// UTC seconds since 1970, the clock commands are stamped and judged by:
// ground and rover must agree on it (NTP or GPS time on a real rover).
double utcNowS();

struct SignerOptions {
  // How long after signing the rover may still carry a command out: longer
  // than the link's one-way delay, short enough that a command stuck in a
  // queue does not move the rover long after the operator approved it.
  double validity_s = 10.0;
  std::function<double()> clock = utcNowS;
};

// The console's side: stamps its operator id, this console's random id,
// the next sequence number, the time and the validity window on each
// command and signs it.
class CommandSigner {
 public:
  explicit CommandSigner(OperatorKey key, std::uint64_t next_sequence = 1,
                         SignerOptions options = {});
  void sign(Command& command);
  // A command of `body` for rover `rover_id`, stamped and signed.
  Command command(std::uint32_t rover_id, CommandBody body);
  const std::string& operatorId() const { return key_.operator_id; }
  std::uint64_t consoleId() const { return console_id_; }
  // consoleName() of this console.
  std::string console() const;
  double validityS() const { return options_.validity_s; }
  void setValidityS(double validity_s) { options_.validity_s = validity_s; }

 private:
  OperatorKey key_;
  std::uint64_t next_sequence_;
  SignerOptions options_;
  std::uint64_t console_id_;
};

struct VerifierOptions {
  // A longer window is refused: a captured command must not stay good.
  double max_validity_s = 600.0;
};

// The rover's side: accepts a command only if it is addressed to this
// rover, signed with a known operator's key, newer than the last command
// accepted from that operator's console, signed after this rover's link
// started and still inside its validity window.
class CommandVerifier {
 public:
  CommandVerifier(std::uint32_t rover_id, const std::vector<OperatorKey>& keys,
                  VerifierOptions options = {});
  // Commands signed before this are refused: sequences are kept in memory
  // only, so this is what stops a command recorded before a restart of the
  // rover from being played again after it.
  void startedAt(double now_s) { started_s_ = now_s; }
  // Accepted (the sequence number is then used up), or the reason for
  // refusing, for the NACK. A Hold is carried out even when late.
  [[nodiscard]] Refusal check(const Command& command, double now_s);

 private:
  std::string problem(const Command& command, double now_s);
  std::string outsideWindow(const Command& command, double now_s) const;
  std::uint32_t rover_id_;
  VerifierOptions options_;
  std::map<std::string, std::vector<std::uint8_t>> keys_;
  std::map<std::pair<std::string, std::uint64_t>, std::uint64_t> last_sequence_;
  std::optional<double> started_s_;
};

}  // namespace ambler::link
