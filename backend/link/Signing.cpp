#include "link/Signing.h"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/hmac.h>
#include <openssl/rand.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "io/Json.h"
#include "link/Codec.h"

namespace ambler::link {

namespace {

std::vector<std::uint8_t> keyFromHex(const io::JsonFields& fields) {
  const std::string hex = fields.string("key_hex");
  if (hex.size() % 2 != 0) fields.fail("key_hex", "has an odd number of hex digits");
  std::vector<std::uint8_t> key;
  for (std::size_t i = 0; i < hex.size(); i += 2) {
    const std::string pair = hex.substr(i, 2);
    if (pair.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos)
      fields.fail("key_hex",
                  "is not hexadecimal (\"" + pair + "\" at digit " + std::to_string(i) + ")");
    key.push_back(std::uint8_t(std::stoi(pair, nullptr, 16)));
  }
  if (key.size() < kMinKeyBytes)
    fields.fail("key_hex", "is " + std::to_string(key.size()) + " bytes; at least " +
                               std::to_string(kMinKeyBytes) + " are needed");
  return key;
}

OperatorKey keyFrom(const io::JsonFields& fields) {
  OperatorKey k{fields.string("operator"), keyFromHex(fields)};
  if (k.operator_id.empty()) fields.fail("operator", "is empty");
  return k;
}

}  // namespace

OperatorKey readOperatorKey(const std::filesystem::path& path) {
  const auto json = io::readJsonFile(path);
  return keyFrom(io::JsonFields(json, path.string()));
}

std::vector<OperatorKey> readOperatorKeys(const std::filesystem::path& path) {
  const auto json = io::readJsonFile(path);
  const io::JsonFields top(json, path.string());
  if (!top.has("operators") || !json["operators"].is_array())
    top.fail("operators", "must be a list of {operator, key_hex}");
  std::vector<OperatorKey> keys;
  for (std::size_t i = 0; i < json["operators"].size(); ++i)
    keys.push_back(keyFrom(io::JsonFields(
        json["operators"][i], path.string() + ": operators[" + std::to_string(i) + "]")));
  return keys;
}

OperatorKey newOperatorKey(const std::string& operator_id) {
  const bool printable = std::all_of(operator_id.begin(), operator_id.end(),
                                     [](char c) { return c > ' ' && c < 127; });
  if (operator_id.empty() || operator_id.size() > 256 || !printable)
    throw std::invalid_argument("operator id '" + operator_id +
                                "' must be 1-256 printable characters without spaces");
  OperatorKey key{operator_id, std::vector<std::uint8_t>(32)};
  if (RAND_bytes(key.key.data(), int(key.key.size())) != 1)
    throw std::runtime_error("OpenSSL could not generate a random key");
  return key;
}

std::string keyHex(const OperatorKey& key) {
  static const char* digits = "0123456789abcdef";
  std::string hex;
  for (const auto byte : key.key) hex += {digits[byte >> 4], digits[byte & 15]};
  return hex;
}

void writeOperatorKey(const std::filesystem::path& path, const OperatorKey& key) {
  // Created owner-only and only if absent, in one step: no moment when the
  // file is readable by others, and no race with another writer.
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0)
    throw std::runtime_error(path.string() +
                             (errno == EEXIST
                                  ? ": exists; not replacing a key"
                                  : ": cannot be written: " + std::string(std::strerror(errno))));
  const std::string text =
      nlohmann::json{{"operator", key.operator_id}, {"key_hex", keyHex(key)}}.dump(2) + "\n";
  const bool written = ::write(fd, text.data(), text.size()) == ssize_t(text.size());
  if (::close(fd) != 0 || !written)
    throw std::runtime_error(path.string() + ": writing the key failed");
}

Hmac hmacSha256(std::span<const std::uint8_t> key, std::span<const std::uint8_t> data) {
  Hmac out{};
  unsigned int length = 0;
  HMAC(EVP_sha256(), key.data(), int(key.size()), data.data(), data.size(), out.data(), &length);
  return out;
}

double utcNowS() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

namespace {

std::uint64_t randomConsoleId() {
  std::uint64_t id = 0;
  while (id == 0)
    if (RAND_bytes(reinterpret_cast<unsigned char*>(&id), sizeof id) != 1)
      throw std::runtime_error("OpenSSL could not generate a console id");
  return id;
}

std::string seconds(double s) {
  std::ostringstream out;
  out.precision(s < 10 ? 2 : 1);
  out << std::fixed << s << " s";
  return out.str();
}

}  // namespace

CommandSigner::CommandSigner(OperatorKey key, std::uint64_t next_sequence, SignerOptions options)
    : key_(std::move(key)),
      next_sequence_(next_sequence),
      options_(std::move(options)),
      console_id_(randomConsoleId()) {}

void CommandSigner::sign(Command& command) {
  command.operator_id = key_.operator_id;
  command.console_id = console_id_;
  command.sequence = next_sequence_++;
  command.time_s = options_.clock();
  command.valid_until_s = command.time_s + options_.validity_s;
  command.hmac = hmacSha256(key_.key, signedContent(command));
}

Command CommandSigner::command(std::uint32_t rover_id, CommandBody body) {
  Command c;
  c.rover_id = rover_id;
  c.body = std::move(body);
  sign(c);
  return c;
}

std::string CommandSigner::console() const { return consoleName(key_.operator_id, console_id_); }

CommandVerifier::CommandVerifier(std::uint32_t rover_id, const std::vector<OperatorKey>& keys,
                                 VerifierOptions options)
    : rover_id_(rover_id), options_(options) {
  for (const auto& k : keys) keys_[k.operator_id] = k.key;
}

Refusal CommandVerifier::check(const Command& c, double now_s) {
  std::string why = problem(c, now_s);
  return why.empty() ? Refusal{} : Refusal::because(std::move(why));
}

std::string CommandVerifier::problem(const Command& c, double now_s) {
  if (c.rover_id != rover_id_)
    return "addressed to rover " + std::to_string(c.rover_id) + ", this is rover " +
           std::to_string(rover_id_);
  if (!c.hmac) return "unsigned command";
  const auto key = keys_.find(c.operator_id);
  if (key == keys_.end()) return "unknown operator \"" + c.operator_id + "\"";
  const Hmac expected = hmacSha256(key->second, signedContent(c));
  if (CRYPTO_memcmp(expected.data(), c.hmac->data(), expected.size()) != 0)
    return "bad signature for operator \"" + c.operator_id + "\"";
  if (c.sequence == 0) return "sequence 0 (sequences start at 1)";
  if (auto late = outsideWindow(c, now_s); !late.empty()) return late;
  auto& last = last_sequence_[{c.operator_id, c.console_id}];
  if (c.sequence == last)
    return "replayed command: sequence " + std::to_string(c.sequence) + " already accepted";
  if (c.sequence < last)
    return "out of order: sequence " + std::to_string(c.sequence) + " after " +
           std::to_string(last);
  last = c.sequence;
  return {};
}

std::string CommandVerifier::outsideWindow(const Command& c, double now_s) const {
  if (started_s_ && c.time_s < *started_s_)
    return "signed " + seconds(*started_s_ - c.time_s) +
           " before this rover's link started (a command from before a restart)";
  if (c.valid_until_s == 0.0) return "no validity window";
  const double window = c.valid_until_s - c.time_s;
  if (window <= 0.0 || window > options_.max_validity_s)
    return "validity window of " + seconds(window) + " (0-" + seconds(options_.max_validity_s) +
           " accepted)";
  if (now_s > c.valid_until_s && !std::holds_alternative<Hold>(c.body))
    return "arrived " + seconds(now_s - c.valid_until_s) +
           " after its validity window closed (signed " + seconds(now_s - c.time_s) +
           " ago, valid for " + seconds(window) + ")";
  return {};
}

}  // namespace ambler::link
