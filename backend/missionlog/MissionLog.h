#pragma once

// The durable record of a mission: every message in and out, every
// proposal the operator decided on, and the products (maps, fits) or the
// parameters that recompute them. One SQLite file per mission in WAL mode;
// each record is its own transaction, synchronous=FULL, so a record is on
// disk when the call returns and survives kill -9 of the ground station.

#include <cstdint>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "link/Codec.h"

struct sqlite3;

namespace ambler::missionlog {

// A log that cannot be opened, read or written; names the file.
class LogError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class Direction { kFromRover, kToRover };

enum class Verdict { kApproved, kRejected, kEdited };

// What the operator did with one proposed move.
struct Decision {
  double time_s = 0.0;
  std::string operator_id;
  std::uint64_t proposal = 0;
  Verdict verdict = Verdict::kApproved;
  std::string detail;  // what was proposed or edited, free text or JSON
};

// A derived product (a map, a fit) as logged: what it is, the parameters
// that recompute it from the logged messages, and its data if stored.
struct LoggedProduct {
  double time_s = 0.0;
  std::string kind;        // "elevation_map", ...
  std::string parameters;  // JSON
  link::Bytes data;
};

struct LoggedMessage {
  std::int64_t id = 0;
  double time_s = 0.0;  // ground clock when it was sent or received
  Direction direction = Direction::kFromRover;
  std::string type;  // link::typeName
  link::Bytes payload;
};

struct Summary {
  std::string mission;
  std::map<std::string, long> from_rover, to_rover;  // message counts by type
  long messages = 0;
  double first_s = 0.0, last_s = 0.0;  // over messages and decisions
  long approved = 0, rejected = 0, edited = 0;
  long products = 0;
  double durationS() const { return last_s - first_s; }
};

// Owns one SQLite connection; move-only.
class Database {
 public:
  Database(const std::filesystem::path& path, bool writable);
  Database(Database&& other) noexcept;
  Database& operator=(Database&&) = delete;
  ~Database();
  sqlite3* handle() const { return db_; }
  const std::filesystem::path& path() const { return path_; }
  void exec(const std::string& sql) const;
  [[noreturn]] void fail(const std::string& what) const;

 private:
  std::string failure(const std::string& what) const;  // what fail() throws
  std::filesystem::path path_;
  bool writable_ = false;
  sqlite3* db_ = nullptr;
};

class MissionLog {
 public:
  // Creates the log, or opens an existing one to append to it.
  MissionLog(const std::filesystem::path& path, const std::string& mission);

  void record(double time_s, const link::Telemetry& message);
  // A batch as it came off the link, in one transaction: one sync to disk
  // for all of it (a group commit), durable when this returns.
  void record(double time_s, const std::vector<link::Telemetry>& messages);
  void record(double time_s, const link::Command& command);
  void record(const Decision& decision);
  void recordProduct(double time_s, const std::string& kind, const std::string& parameters_json,
                     const link::Bytes& data = {});
  // An event of a walk in a sentence: an "event" product, {"what": ...}.
  void recordEvent(double time_s, const std::string& what);

 private:
  void insertMessage(double time_s, Direction direction, const std::string& type,
                     std::uint32_t rover_id, const std::string& operator_id, std::int64_t sequence,
                     const link::Bytes& payload);
  Database db_;
};

// Read-only access for replay and summaries; another process may still be
// writing the log.
class MissionLogReader {
 public:
  explicit MissionLogReader(const std::filesystem::path& path);

  Summary summary() const;
  // Messages with from_s <= time_s < to_s, in time order.
  std::vector<LoggedMessage> messages(double from_s, double to_s) const;
  std::vector<Decision> decisions() const;
  std::vector<LoggedProduct> products() const;  // in time order

 private:
  void checkColumns() const;
  Database db_;
};

std::string verdictName(Verdict verdict);

}  // namespace ambler::missionlog
