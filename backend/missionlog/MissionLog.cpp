#include "missionlog/MissionLog.h"

#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <system_error>
#include <utility>

namespace ambler::missionlog {

namespace {

constexpr int kSchemaVersion = 1;

const char* kSchema = R"(
CREATE TABLE IF NOT EXISTS meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS messages(
  id INTEGER PRIMARY KEY,
  time_s REAL NOT NULL,
  direction TEXT NOT NULL CHECK(direction IN ('from_rover', 'to_rover')),
  type TEXT NOT NULL,
  rover_id INTEGER NOT NULL,
  operator TEXT,
  sequence INTEGER,
  payload BLOB NOT NULL);
CREATE INDEX IF NOT EXISTS messages_by_time ON messages(time_s);
CREATE TABLE IF NOT EXISTS decisions(
  id INTEGER PRIMARY KEY,
  time_s REAL NOT NULL,
  operator TEXT NOT NULL,
  proposal INTEGER NOT NULL,
  verdict TEXT NOT NULL CHECK(verdict IN ('approved', 'rejected', 'edited')),
  detail TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS products(
  id INTEGER PRIMARY KEY,
  time_s REAL NOT NULL,
  kind TEXT NOT NULL,
  parameters TEXT NOT NULL,
  data BLOB);
)";

// One prepared statement; binds by position from 1, steps, finalizes.
class Statement {
 public:
  Statement(const Database& db, const char* sql) : db_(db) {
    if (sqlite3_prepare_v2(db.handle(), sql, -1, &stmt_, nullptr) != SQLITE_OK)
      db.fail("preparing a query");
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  Statement& bind(int i, double v) { return check(sqlite3_bind_double(stmt_, i, v)); }
  Statement& bind(int i, std::int64_t v) { return check(sqlite3_bind_int64(stmt_, i, v)); }
  Statement& bind(int i, const std::string& v) {
    return check(sqlite3_bind_text(stmt_, i, v.data(), int(v.size()), SQLITE_TRANSIENT));
  }
  Statement& bind(int i, const link::Bytes& v) {
    return check(sqlite3_bind_blob(stmt_, i, v.data(), int(v.size()), SQLITE_TRANSIENT));
  }
  Statement& bindNull(int i) { return check(sqlite3_bind_null(stmt_, i)); }

  // True while there is a row to read.
  bool step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc != SQLITE_DONE) db_.fail("reading or writing");
    return false;
  }
  // Typed reads: a value of another storage class (a foreign or damaged
  // log) is refused, naming the column, instead of read as 0 or "".
  bool isNull(int col) const { return sqlite3_column_type(stmt_, col) == SQLITE_NULL; }
  double real(int col) const {
    expect(col, {SQLITE_FLOAT, SQLITE_INTEGER}, "a number");
    const double v = sqlite3_column_double(stmt_, col);
    if (!std::isfinite(v)) bad(col, "finite");
    return v;
  }
  std::int64_t integer(int col) const {
    expect(col, {SQLITE_INTEGER}, "a whole number");
    return sqlite3_column_int64(stmt_, col);
  }
  // NULL reads as "" (the operator of a message from the rover).
  std::string text(int col) const {
    expect(col, {SQLITE_TEXT, SQLITE_NULL}, "text");
    const auto* p = sqlite3_column_text(stmt_, col);
    return p ? std::string(reinterpret_cast<const char*>(p), sqlite3_column_bytes(stmt_, col))
             : std::string();
  }
  link::Bytes blob(int col) const {
    expect(col, {SQLITE_BLOB, SQLITE_NULL}, "bytes");
    const auto* p = static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt_, col));
    return p ? link::Bytes(p, p + sqlite3_column_bytes(stmt_, col)) : link::Bytes();
  }

 private:
  Statement& check(int rc) {
    if (rc != SQLITE_OK) db_.fail("binding a value");
    return *this;
  }
  const char* name(int col) const {
    const char* n = sqlite3_column_name(stmt_, col);
    return n ? n : "?";
  }
  void expect(int col, std::initializer_list<int> types, const char* what) const {
    const int type = sqlite3_column_type(stmt_, col);
    if (std::find(types.begin(), types.end(), type) == types.end()) bad(col, what);
  }
  [[noreturn]] void bad(int col, const char* what) const {
    throw LogError(db_.path().string() + ": a value of column " + name(col) + " is not " + what +
                   " (a damaged or foreign mission log)");
  }
  const Database& db_;
  sqlite3_stmt* stmt_ = nullptr;
};

Verdict verdictFrom(const std::string& name, const Database& db) {
  if (name == "approved") return Verdict::kApproved;
  if (name == "rejected") return Verdict::kRejected;
  if (name == "edited") return Verdict::kEdited;
  throw LogError(db.path().string() + ": unknown verdict \"" + name + "\"");
}

}  // namespace

std::string verdictName(Verdict verdict) {
  switch (verdict) {
    case Verdict::kApproved:
      return "approved";
    case Verdict::kRejected:
      return "rejected";
    case Verdict::kEdited:
      return "edited";
  }
  return "?";
}

Database::Database(const std::filesystem::path& path, bool writable)
    : path_(path), writable_(writable) {
  // The error_code forms: a name the file system refuses (too long, say) is
  // left to SQLite to name rather than thrown as a filesystem_error.
  std::error_code ignored;
  if (!writable && !std::filesystem::exists(path, ignored))
    throw LogError(path.string() + ": no such file");
  if (std::filesystem::is_directory(path, ignored))
    throw LogError(path.string() + ": is a folder, not a mission log");
  const auto folder = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  if (writable && !std::filesystem::is_directory(folder, ignored))
    throw LogError(path.string() + ": there is no folder " + folder.string() +
                   " to write the mission log in");
  const int flags = writable ? SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE : SQLITE_OPEN_READONLY;
  if (sqlite3_open_v2(path.c_str(), &db_, flags, nullptr) != SQLITE_OK) {
    // SQLite allocates the handle even then, and a constructor that throws
    // runs no destructor.
    const std::string why = failure("opening");
    sqlite3_close_v2(std::exchange(db_, nullptr));
    throw LogError(why);
  }
  sqlite3_busy_timeout(db_, 2000);
}

Database::Database(Database&& other) noexcept
    : path_(std::move(other.path_)),
      writable_(other.writable_),
      db_(std::exchange(other.db_, nullptr)) {}

Database::~Database() {
  // A log closed cleanly becomes one self-contained file again: in WAL mode
  // every later reader, even a read-only one, would leave -wal and -shm
  // files beside it. Another connection still open keeps it in WAL.
  if (db_ && writable_) {
    sqlite3_busy_timeout(db_, 0);
    sqlite3_exec(db_, "PRAGMA journal_mode=DELETE", nullptr, nullptr, nullptr);
  }
  sqlite3_close_v2(db_);
}

void Database::exec(const std::string& sql) const {
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, nullptr) != SQLITE_OK) fail("writing");
}

std::string Database::failure(const std::string& what) const {
  return path_.string() + ": " + what +
         " the mission log: " + (db_ ? sqlite3_errmsg(db_) : "out of memory");
}

void Database::fail(const std::string& what) const { throw LogError(failure(what)); }

MissionLog::MissionLog(const std::filesystem::path& path, const std::string& mission)
    : db_(path, true) {
  db_.exec("PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL;");
  db_.exec(kSchema);
  Statement version(db_, "SELECT value FROM meta WHERE key = 'schema_version'");
  if (version.step()) {
    if (version.text(0) != std::to_string(kSchemaVersion))
      throw LogError(path.string() + ": mission log schema " + version.text(0) +
                     ", this program writes " + std::to_string(kSchemaVersion));
    return;
  }
  Statement meta(db_, "INSERT INTO meta(key, value) VALUES ('schema_version', ?), ('mission', ?)");
  meta.bind(1, std::to_string(kSchemaVersion)).bind(2, mission).step();
}

void MissionLog::insertMessage(double time_s, Direction direction, const std::string& type,
                               std::uint32_t rover_id, const std::string& operator_id,
                               std::int64_t sequence, const link::Bytes& payload) {
  Statement s(db_,
              "INSERT INTO messages(time_s, direction, type, rover_id, operator, sequence, payload)"
              " VALUES (?, ?, ?, ?, ?, ?, ?)");
  s.bind(1, time_s)
      .bind(2, std::string(direction == Direction::kFromRover ? "from_rover" : "to_rover"))
      .bind(3, type)
      .bind(4, std::int64_t(rover_id));
  if (direction == Direction::kToRover)
    s.bind(5, operator_id).bind(6, sequence);
  else
    s.bindNull(5).bindNull(6);
  s.bind(7, payload).step();
}

void MissionLog::record(double time_s, const link::Telemetry& m) {
  insertMessage(time_s, Direction::kFromRover, link::typeName(m.body), m.rover_id, "", 0,
                link::encode(m));
}

void MissionLog::record(double time_s, const std::vector<link::Telemetry>& messages) {
  if (messages.size() == 1) return record(time_s, messages.front());
  if (messages.empty()) return;
  db_.exec("BEGIN");
  try {
    for (const auto& m : messages) record(time_s, m);
  } catch (...) {
    db_.exec("ROLLBACK");
    throw;
  }
  db_.exec("COMMIT");
}

void MissionLog::record(double time_s, const link::Command& c) {
  insertMessage(time_s, Direction::kToRover, link::typeName(c.body), c.rover_id, c.operator_id,
                std::int64_t(c.sequence), link::encode(c));
}

void MissionLog::record(const Decision& d) {
  Statement s(db_,
              "INSERT INTO decisions(time_s, operator, proposal, verdict, detail)"
              " VALUES (?, ?, ?, ?, ?)");
  s.bind(1, d.time_s)
      .bind(2, d.operator_id)
      .bind(3, std::int64_t(d.proposal))
      .bind(4, verdictName(d.verdict))
      .bind(5, d.detail)
      .step();
}

void MissionLog::recordEvent(double time_s, const std::string& what) {
  recordProduct(time_s, "event", nlohmann::json{{"what", what}}.dump());
}

void MissionLog::recordProduct(double time_s, const std::string& kind,
                               const std::string& parameters_json, const link::Bytes& data) {
  Statement s(db_, "INSERT INTO products(time_s, kind, parameters, data) VALUES (?, ?, ?, ?)");
  s.bind(1, time_s).bind(2, kind).bind(3, parameters_json);
  if (data.empty())
    s.bindNull(4);
  else
    s.bind(4, data);
  s.step();
}

MissionLogReader::MissionLogReader(const std::filesystem::path& path) : db_(path, false) {
  // The log may come from anywhere: SQLite's advice for untrusted files
  // (no schema-defined functions, no writes to its own tables, cell sizes
  // checked).
  sqlite3_db_config(db_.handle(), SQLITE_DBCONFIG_DEFENSIVE, 1, nullptr);
  sqlite3_db_config(db_.handle(), SQLITE_DBCONFIG_TRUSTED_SCHEMA, 0, nullptr);
  sqlite3_exec(db_.handle(), "PRAGMA cell_size_check = ON", nullptr, nullptr, nullptr);
  // A file that is not SQLite, or SQLite without our tables, fails here.
  sqlite3_stmt* probe = nullptr;
  const int rc = sqlite3_prepare_v2(
      db_.handle(), "SELECT value FROM meta WHERE key = 'schema_version'", -1, &probe, nullptr);
  const bool found = rc == SQLITE_OK && sqlite3_step(probe) == SQLITE_ROW;
  const std::string problem = rc == SQLITE_OK ? "no schema version" : sqlite3_errmsg(db_.handle());
  const auto* version = found ? sqlite3_column_text(probe, 0) : nullptr;
  const std::string version_text = version ? reinterpret_cast<const char*>(version) : "";
  sqlite3_finalize(probe);
  if (!found) throw LogError(path.string() + ": not a mission log (" + problem + ")");
  if (version_text != std::to_string(kSchemaVersion))
    throw LogError(path.string() + ": mission log schema '" + version_text.substr(0, 40) +
                   "', this program reads " + std::to_string(kSchemaVersion));
  checkColumns();
}

void MissionLogReader::checkColumns() const {
  const std::pair<const char*, std::vector<std::string>> tables[] = {
      {"messages",
       {"id", "time_s", "direction", "type", "rover_id", "operator", "sequence", "payload"}},
      {"decisions", {"id", "time_s", "operator", "proposal", "verdict", "detail"}},
      {"products", {"id", "time_s", "kind", "parameters", "data"}}};
  for (const auto& [table, columns] : tables) {
    Statement info(db_,
                   (std::string("SELECT name FROM pragma_table_info('") + table + "')").c_str());
    std::vector<std::string> found;
    while (info.step()) found.push_back(info.text(0));
    for (const auto& column : columns)
      if (std::find(found.begin(), found.end(), column) == found.end())
        throw LogError(db_.path().string() + ": not a mission log (table " + table +
                       (found.empty() ? " is missing)" : " has no column " + column + ")"));
  }
}

Summary MissionLogReader::summary() const {
  Summary s;
  Statement mission(db_, "SELECT value FROM meta WHERE key = 'mission'");
  if (mission.step()) s.mission = mission.text(0);
  Statement counts(db_, "SELECT direction, type, COUNT(*) FROM messages GROUP BY direction, type");
  while (counts.step()) {
    auto& table = counts.text(0) == "from_rover" ? s.from_rover : s.to_rover;
    table[counts.text(1)] = long(counts.integer(2));
    s.messages += long(counts.integer(2));
  }
  Statement span(db_,
                 "SELECT MIN(t) AS time_s, MAX(t) AS time_s FROM (SELECT time_s AS t FROM messages"
                 " UNION ALL SELECT time_s FROM decisions)");
  if (span.step() && !span.isNull(0)) s.first_s = span.real(0), s.last_s = span.real(1);
  Statement verdicts(db_, "SELECT verdict, COUNT(*) FROM decisions GROUP BY verdict");
  while (verdicts.step()) {
    const long n = long(verdicts.integer(1));
    switch (verdictFrom(verdicts.text(0), db_)) {
      case Verdict::kApproved:
        s.approved = n;
        break;
      case Verdict::kRejected:
        s.rejected = n;
        break;
      case Verdict::kEdited:
        s.edited = n;
        break;
    }
  }
  Statement products(db_, "SELECT COUNT(*) FROM products");
  if (products.step()) s.products = long(products.integer(0));
  return s;
}

std::vector<LoggedMessage> MissionLogReader::messages(double from_s, double to_s) const {
  Statement s(db_,
              "SELECT id, time_s, direction, type, payload FROM messages"
              " WHERE time_s >= ? AND time_s < ? ORDER BY time_s, id");
  s.bind(1, from_s).bind(2, to_s);
  std::vector<LoggedMessage> out;
  while (s.step())
    out.push_back({s.integer(0), s.real(1),
                   s.text(2) == "from_rover" ? Direction::kFromRover : Direction::kToRover,
                   s.text(3), s.blob(4)});
  return out;
}

std::vector<Decision> MissionLogReader::decisions() const {
  Statement s(db_,
              "SELECT time_s, operator, proposal, verdict, detail FROM decisions ORDER BY time_s, "
              "id");
  std::vector<Decision> out;
  while (s.step())
    out.push_back({s.real(0), s.text(1), std::uint64_t(s.integer(2)), verdictFrom(s.text(3), db_),
                   s.text(4)});
  return out;
}

std::vector<LoggedProduct> MissionLogReader::products() const {
  Statement s(db_, "SELECT time_s, kind, parameters, data FROM products ORDER BY time_s, id");
  std::vector<LoggedProduct> out;
  while (s.step()) out.push_back({s.real(0), s.text(1), s.text(2), s.blob(3)});
  return out;
}

}  // namespace ambler::missionlog
