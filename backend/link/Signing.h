#pragma once

// Command authentication: HMAC-SHA256 (OpenSSL) over a command's content
// with a key shared in advance between one operator and the rover, plus a
// sequence number per operator so that a recorded command cannot be played
// again. A console without a key can watch but never command.

#include <cstdint>
#include <filesystem>
#include <map>
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

// The console's side: stamps its operator id and the next sequence number
// on each command and signs it.
class CommandSigner {
 public:
  explicit CommandSigner(OperatorKey key, std::uint64_t next_sequence = 1);
  void sign(Command& command);
  const std::string& operatorId() const { return key_.operator_id; }

 private:
  OperatorKey key_;
  std::uint64_t next_sequence_;
};

// The rover's side: accepts a command only if it is addressed to this
// rover, signed with a known operator's key, and newer than the last
// command accepted from that operator.
class CommandVerifier {
 public:
  CommandVerifier(std::uint32_t rover_id, const std::vector<OperatorKey>& keys);
  // Accepted (the sequence number is then used up), or the reason for
  // refusing, for the NACK.
  Refusal check(const Command& command);

 private:
  std::string problem(const Command& command);
  std::uint32_t rover_id_;
  std::map<std::string, std::vector<std::uint8_t>> keys_;
  std::map<std::string, std::uint64_t> last_sequence_;
};

}  // namespace ambler::link
