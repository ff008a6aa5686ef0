#include "missionlog/MissionLog.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <vector>

namespace ambler::missionlog {
namespace {

class MissionLogTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("ambler_missionlog_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

link::Command bodyMove(std::uint64_t sequence) {
  link::Command c;
  c.rover_id = 1;
  c.operator_id = "alice";
  c.sequence = sequence;
  c.body = link::BodyMove{0.0, 0.5, 0.0, 0.0};
  c.hmac = link::Hmac{};
  return c;
}

TEST_F(MissionLogTest, RecordsComeBackInTimeOrderAndAreSummarised) {
  const auto path = dir_ / "mission.sqlite";
  {
    MissionLog log(path, "course seed 1");
    log.record(10.0, link::Telemetry{1, 9.9, link::Heartbeat{1, false, {}, {}, {}}});
    log.record(11.0, link::Telemetry{1, 10.9, link::Heartbeat{2, true, "Hold from alice", {}, {}}});
    log.record(10.5, link::Telemetry{1, 10.4, link::BodyState{1, 2, 3, 0.1, false}});
    log.record(12.0, bodyMove(1));
    log.record(Decision{11.5, "alice", 1, Verdict::kApproved, "body move 0.5 m"});
    log.record(Decision{13.0, "alice", 2, Verdict::kRejected, "foothold in shadow"});
    log.record(Decision{14.0, "bob", 3, Verdict::kEdited, "{\"foothold\": [1, 2]}"});
    log.recordProduct(10.6, "elevation_map", "{\"resolution\": 0.1}");
  }
  const MissionLogReader reader(path);
  const Summary s = reader.summary();
  EXPECT_EQ(s.mission, "course seed 1");
  EXPECT_EQ(s.messages, 4);
  EXPECT_EQ(s.from_rover.at("Heartbeat"), 2);
  EXPECT_EQ(s.from_rover.at("BodyState"), 1);
  EXPECT_EQ(s.to_rover.at("BodyMove"), 1);
  EXPECT_EQ(s.approved, 1);
  EXPECT_EQ(s.rejected, 1);
  EXPECT_EQ(s.edited, 1);
  EXPECT_EQ(s.products, 1);
  EXPECT_DOUBLE_EQ(s.first_s, 10.0);
  EXPECT_DOUBLE_EQ(s.durationS(), 4.0);

  const auto messages = reader.messages(10.2, 12.0);  // [from, to)
  ASSERT_EQ(messages.size(), 2u);
  EXPECT_EQ(messages[0].type, "BodyState");
  EXPECT_EQ(messages[1].type, "Heartbeat");
  EXPECT_EQ(std::get<link::Heartbeat>(link::decodeTelemetry(messages[1].payload).body).count, 2u);
  const auto all = reader.messages(0, 100);
  ASSERT_EQ(all.size(), 4u);
  EXPECT_EQ(all.back().direction, Direction::kToRover);
  EXPECT_EQ(link::decodeCommand(all.back().payload).operator_id, "alice");

  const auto decisions = reader.decisions();
  ASSERT_EQ(decisions.size(), 3u);
  EXPECT_EQ(decisions[1].detail, "foothold in shadow");
  EXPECT_EQ(decisions[2].verdict, Verdict::kEdited);

  const auto products = reader.products();
  ASSERT_EQ(products.size(), 1u);
  EXPECT_EQ(products[0].kind, "elevation_map");
  EXPECT_EQ(products[0].parameters, "{\"resolution\": 0.1}");
  EXPECT_DOUBLE_EQ(products[0].time_s, 10.6);
  EXPECT_TRUE(products[0].data.empty());
}

TEST_F(MissionLogTest, ReopeningAppendsWithoutLosingRecords) {
  const auto path = dir_ / "mission.sqlite";
  MissionLog(path, "m").record(1.0, bodyMove(1));
  MissionLog(path, "ignored: the log keeps its name").record(2.0, bodyMove(2));
  const Summary s = MissionLogReader(path).summary();
  EXPECT_EQ(s.to_rover.at("BodyMove"), 2);
  EXPECT_EQ(s.mission, "m");
}

TEST_F(MissionLogTest, FilesThatAreNotMissionLogsAreNamedAndRefused) {
  auto expectRefused = [](const std::filesystem::path& path, const std::string& words) {
    try {
      MissionLogReader reader(path);
      FAIL() << path;
    } catch (const LogError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path.string()), std::string::npos) << what;
      EXPECT_NE(what.find(words), std::string::npos) << what;
    }
  };
  expectRefused(dir_ / "missing.sqlite", "no such file");
  std::ofstream(dir_ / "text.sqlite") << "this is not a database, just some words to fill a page";
  expectRefused(dir_ / "text.sqlite", "not a mission log");
  // A real SQLite file but someone else's.
  {
    Database other(dir_ / "other.sqlite", true);
    other.exec("CREATE TABLE t(x);");
  }
  expectRefused(dir_ / "other.sqlite", "not a mission log (no such table: meta)");
  expectRefused(dir_, "is a folder, not a mission log");
  const auto expectNotCreated = [](const std::filesystem::path& path, const std::string& words) {
    try {
      MissionLog log(path, "mission");
      FAIL() << "created " << path;
    } catch (const LogError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  expectNotCreated(
      dir_ / "no-such-folder" / "walk.sqlite",
      "there is no folder " + (dir_ / "no-such-folder").string() + " to write the mission log in");
  // SQLite's open itself fails (a name longer than the file system takes).
  // The handle it allocates anyway is closed (the sanitized suite finds the
  // leak otherwise).
  expectNotCreated(dir_ / (std::string(300, 'w') + ".sqlite"),
                   "opening the mission log: unable to open database file");
}

// A log's damage is named whatever form it takes: a wrong schema version, a
// missing table or column, values of the wrong type, a cut file.
TEST_F(MissionLogTest, DamagedOrForeignLogsAreRefusedNamingTheProblem) {
  auto refusal = [](const std::filesystem::path& path) -> std::string {
    try {
      const MissionLogReader reader(path);
      (void)reader.summary();
      (void)reader.messages(-INFINITY, INFINITY);
      (void)reader.decisions();
      (void)reader.products();
    } catch (const LogError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path.string() + ": ", 0), 0u) << e.what();
      return e.what();
    }
    return "accepted";
  };
  auto logWith = [&](const std::string& name, const std::string& sql) {
    const auto path = dir_ / name;
    {
      MissionLog log(path, "m");
      log.record(1.0, bodyMove(1));
      log.record(Decision{2.0, "alice", 1, Verdict::kApproved, "ok"});
    }
    if (!sql.empty()) Database(path, true).exec(sql);
    return path;
  };
  EXPECT_EQ(refusal(logWith("good.sqlite", "")), "accepted");
  EXPECT_NE(refusal(logWith("v2.sqlite",
                            "UPDATE meta SET value = '2' WHERE key = "
                            "'schema_version'"))
                .find("mission log schema '2', this program reads 1"),
            std::string::npos);
  EXPECT_NE(refusal(logWith("no-products.sqlite", "DROP TABLE products"))
                .find("table products is missing"),
            std::string::npos);
  EXPECT_NE(refusal(logWith("no-detail.sqlite", "ALTER TABLE decisions DROP COLUMN detail"))
                .find("table decisions has no column detail"),
            std::string::npos);
  EXPECT_NE(refusal(logWith("text-time.sqlite", "UPDATE messages SET time_s = 'noon'"))
                .find("column time_s is not a number"),
            std::string::npos);
  EXPECT_NE(refusal(logWith("int-payload.sqlite", "UPDATE messages SET payload = 12"))
                .find("column payload is not bytes"),
            std::string::npos);
  EXPECT_NE(
      refusal(logWith("inf-time.sqlite", "UPDATE decisions SET time_s = 9e999")).find("not finite"),
      std::string::npos);

  // Cut to its first page, and its first 100 bytes (inside SQLite's header).
  for (const std::uintmax_t size : {4096u, 100u}) {
    const auto path = logWith("cut-" + std::to_string(size) + ".sqlite", "");
    std::filesystem::resize_file(path, size);
    EXPECT_NE(refusal(path), "accepted") << size;
  }
}

// A log closed cleanly is one file: reading it leaves nothing beside it.
TEST_F(MissionLogTest, AClosedLogIsOneFileAndReadingItLeavesNoOther) {
  const auto path = dir_ / "mission.sqlite";
  MissionLog(path, "m").record(1.0, bodyMove(1));
  EXPECT_EQ(MissionLogReader(path).summary().messages, 1);
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir_))
    names.push_back(entry.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"mission.sqlite"});
}

// A child process writes records and reports each one acknowledged (the
// call returned) through a pipe; the parent kills it with SIGKILL midway.
// Every acknowledged record must be in the log.
TEST_F(MissionLogTest, AcknowledgedRecordsSurviveKillMinus9) {
  const auto path = dir_ / "mission.sqlite";
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::close(fds[0]);
    MissionLog log(path, "crash test");
    for (std::uint64_t i = 1; i <= 100000; ++i) {
      log.record(double(i), bodyMove(i));
      if (::write(fds[1], &i, sizeof i) != sizeof i) ::_exit(2);
    }
    ::_exit(0);
  }
  ::close(fds[1]);
  std::uint64_t acked = 0, i = 0;
  while (acked < 50 && ::read(fds[0], &i, sizeof i) == sizeof i) acked = i;
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  ::close(fds[0]);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the writer finished before it was killed";
  ASSERT_EQ(acked, 50u);
  const MissionLogReader reader(path);
  const auto messages = reader.messages(0, 1e9);
  ASSERT_GE(messages.size(), acked);
  for (std::uint64_t k = 1; k <= acked; ++k)
    EXPECT_EQ(link::decodeCommand(messages[k - 1].payload).sequence, k);
}

}  // namespace
}  // namespace ambler::missionlog
