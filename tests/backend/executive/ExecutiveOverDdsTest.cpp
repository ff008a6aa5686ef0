// The whole chain over DDS on loopback, with ambler-sim in its own process:
// the executive walks with scripted approvals and the
// log holds every command and acknowledgement; a console killed mid-walk
// loses no acknowledged command, and the simulator holds when it falls
// silent. Each test process takes its own domain.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "../../TempDir.h"
#include "InstalledConfig.h"
#include "executive/WalkExecutive.h"
#include "link/Signing.h"
#include "link/dds/DdsMessages.h"
#include "missionlog/ReplayLinks.h"
#include "rover/SimulatedRover.h"

namespace ambler::executive {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

std::uint32_t testDomain() { return 20 + std::uint32_t(::getpid()) % 200; }

using testing_config::ground;
using testing_config::simulator;

link::OperatorKey alice() { return {"alice", std::vector<std::uint8_t>(32, 7)}; }

std::string aliceHex() {
  std::string hex;
  for (int i = 0; i < 32; ++i) hex += "07";
  return hex;
}

double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// ambler-sim serving `domain` until the test ends.
class SimProcess {
 public:
  // `time_scale`: ambler-sim's --time-scale (0: every move at once).
  SimProcess(const TempDir& dir, std::uint32_t domain, double link_timeout_s,
             double time_scale = 0.0) {
    const auto keys = dir / "operators.json";
    std::ofstream(keys) << R"({"operators": [{"operator": "alice", "key_hex": ")" << aliceHex()
                        << R"("}]})";
    pid_ = ::fork();
    if (pid_ == 0) {
      const std::string d = std::to_string(domain), t = std::to_string(link_timeout_s),
                        scale = std::to_string(time_scale);
      ::execl(AMBLER_SIM, AMBLER_SIM, "--domain", d.c_str(), "--keys", keys.c_str(),
              "--link-timeout", t.c_str(), "--heartbeat-ms", "200", "--duration", "120",
              "--time-scale", scale.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
  }
  ~SimProcess() {
    if (pid_ > 0) stop(SIGTERM);
  }
  void stop(int signal) {
    ::kill(pid_, signal);
    ::waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
};

// ambler-cli drive as alice on `domain`, logging to `log`, with `options`:
// its process and its standard output, to read line by line.
std::pair<pid_t, FILE*> startDrive(const TempDir& dir, std::uint32_t domain,
                                   const std::filesystem::path& log,
                                   std::vector<std::string> options) {
  const auto key = dir / "alice.json";
  std::ofstream(key) << R"({"operator": "alice", "key_hex": ")" << aliceHex() << R"("})";
  std::vector<std::string> argv = {AMBLER_CLI, "drive", "--domain", std::to_string(domain),
                                   "--key",    key,     "--log",    log};
  argv.insert(argv.end(), options.begin(), options.end());
  int out[2];
  if (::pipe(out) != 0) return {-1, nullptr};
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(out[0]), ::close(out[1]);
    return {-1, nullptr};
  }
  if (pid == 0) {
    ::dup2(out[1], STDOUT_FILENO);
    ::close(out[0]);
    std::vector<char*> args;
    for (auto& a : argv) args.push_back(a.data());
    args.push_back(nullptr);
    ::execv(AMBLER_CLI, args.data());
    ::_exit(127);
  }
  ::close(out[1]);
  return {pid, ::fdopen(out[0], "r")};
}

// An auto-approving ambler-cli drive killed with SIGKILL as soon as the
// rover has acknowledged its first BodyMove, so that the move is still
// under way on a rover whose moves take their time. False if it never
// moved the rover within a minute.
[[nodiscard]] bool killADriveMidBodyMove(const TempDir& dir, std::uint32_t domain) {
  const auto [console, lines] =
      startDrive(dir, domain, dir / "first.db", {"--steps", "5", "--auto-approve"});
  if (console < 0) return false;
  char line[4096];
  bool moving = false;
  const auto start = Clock::now();
  while (!moving && secondsSince(start) < 60 && std::fgets(line, sizeof line, lines)) {
    const auto j = nlohmann::json::parse(line);
    moving = j.contains("ack") && j["accepted"].get<bool>() && j["command"] == "BodyMove";
  }
  ::kill(console, SIGKILL);
  std::fclose(lines);
  ::waitpid(console, nullptr, 0);
  return moving;
}

// What a log holds: commands by sequence, acknowledgements by sequence.
struct LoggedTraffic {
  std::map<std::uint64_t, std::string> commands;
  std::map<std::uint64_t, link::CommandAck> acks;
};

LoggedTraffic readTraffic(const std::filesystem::path& path) {
  LoggedTraffic out;
  for (const auto& m : missionlog::MissionLogReader(path).messages(0, 1e300)) {
    if (m.direction == missionlog::Direction::kToRover) {
      const auto c = link::decodeCommand(m.payload);
      out.commands[c.sequence] = link::typeName(c.body);
    } else if (m.type == "CommandAck") {
      const auto a = std::get<link::CommandAck>(link::decodeTelemetry(m.payload).body);
      out.acks[a.sequence] = a;
    }
  }
  return out;
}

TEST(ExecutiveOverDds, WalksFiveApprovedStepsWithAmblerSimAndLogsEveryCommandAndAck) {
  TempDir dir;
  const auto domain = testDomain();
  SimProcess sim(dir, domain, 3.0);
  link::dds::DdsLink dds(domain, 1);
  missionlog::MissionLog log(dir / "mission.db", "end to end");
  missionlog::RecordingLink recording(dds, log);
  link::CommandSigner signer(alice());
  ApprovalGate gate([&](const missionlog::Decision& d) { log.record(d); });
  ExecutiveOptions options;
  options.steps = 5;
  WalkExecutive executive(recording, signer, gate, ground(), options);
  executive.onProduct([&](double t, const std::string& kind, const std::string& parameters) {
    log.recordProduct(t, kind, parameters);
  });

  // The script: reject the first proposal, resume, approve every other.
  std::set<std::uint64_t> decided;
  const auto start = Clock::now();
  executive.start(link::utcNowS());
  while (executive.phase() != Phase::kDone && secondsSince(start) < 60) {
    const double now = link::utcNowS();
    executive.poll(now, 50ms);
    if (const auto& p = gate.pending(); p && decided.insert(p->id).second) {
      if (decided.size() == 1)
        EXPECT_FALSE(gate.reject(p->id, "alice", now, "scripted rejection").refused());
      else
        EXPECT_FALSE(gate.approve(p->id, "alice", now).refused()) << p->interlocks.firstFailure();
    }
    if (executive.phase() == Phase::kSuspended) {
      ASSERT_EQ(decided.size(), 1u) << executive.events().back().what;
      executive.resume(now);
    }
  }
  ASSERT_EQ(executive.phase(), Phase::kDone) << executive.events().back().what;
  EXPECT_EQ(executive.stepsDone(), 5);

  const auto traffic = readTraffic(dir / "mission.db");
  int moves = 0;
  for (const auto& [sequence, type] : traffic.commands) {
    if (type == "GroundHeartbeat") continue;  // acknowledged only when refused
    const auto ack = traffic.acks.find(sequence);
    ASSERT_NE(ack, traffic.acks.end()) << type << " " << sequence << " has no ack in the log";
    EXPECT_TRUE(ack->second.accepted) << type << ": " << ack->second.reason;
    moves += type == "LegMove" || type == "BodyMove";
  }
  EXPECT_GE(moves, 5);
  const auto summary = missionlog::MissionLogReader(dir / "mission.db").summary();
  EXPECT_EQ(summary.approved, 5);
  EXPECT_EQ(summary.rejected, 1);
  // Each mapped scan, with what recomputes its map from the logged image
  // and the pose correction it was placed with;
  // each ended task of the task tree, for the module-timing plot; each
  // proposal, for the replay's Step approval dock (five approved, one
  // rejected).
  std::map<std::string, long> kinds;
  for (const auto& product : missionlog::MissionLogReader(dir / "mission.db").products())
    ++kinds[product.kind];
  EXPECT_EQ(kinds["elevation_map"], summary.from_rover.at("RangeImage"));
  EXPECT_EQ(kinds["pose_correction"], summary.from_rover.at("RangeImage"));
  EXPECT_GT(kinds["task"], 0);
  EXPECT_EQ(kinds["proposal"], 6);
  EXPECT_EQ(summary.products,
            kinds["elevation_map"] + kinds["pose_correction"] + kinds["task"] + kinds["proposal"]);
}

// A console (ambler-cli drive) in its own process, killed with SIGKILL
// while it walks; it prints each acknowledgement after logging it.
TEST(ExecutiveOverDds, AConsoleKilledMidWalkLosesNoAcknowledgedCommandAndTheRoverHolds) {
  TempDir dir;
  const auto domain = testDomain();
  const double link_timeout_s = 2.0;
  SimProcess sim(dir, domain, link_timeout_s);
  const auto log = dir / "mission.db";
  const auto [console, lines] = startDrive(dir, domain, log, {"--steps", "40", "--auto-approve"});
  ASSERT_GE(console, 0);
  link::dds::DdsLink monitor(domain, 1);  // no key: it can only watch

  std::set<std::uint64_t> acked;
  int moves_acked = 0;
  char line[4096];
  const auto start = Clock::now();
  while (moves_acked < 8 && secondsSince(start) < 60 && std::fgets(line, sizeof line, lines)) {
    const auto j = nlohmann::json::parse(line);
    if (!j.contains("ack") || !j["accepted"].get<bool>()) continue;
    acked.insert(j["ack"].get<std::uint64_t>());
    const auto type = j["command"].get<std::string>();
    moves_acked += type == "LegMove" || type == "BodyMove";
  }
  ASSERT_EQ(moves_acked, 8) << "the console did not walk";
  for (const auto& t : monitor.receive(0ms))
    if (const auto* h = std::get_if<link::Heartbeat>(&t.body)) {
      ASSERT_FALSE(h->holding) << "held while the console was alive: " << h->hold_reason;
    }
  ::kill(console, SIGKILL);
  const auto killed = Clock::now();
  while (std::fgets(line, sizeof line, lines)) {  // what it printed before dying
    const auto j = nlohmann::json::parse(line, nullptr, false);
    if (!j.is_discarded() && j.contains("ack")) acked.insert(j["ack"].get<std::uint64_t>());
  }
  std::fclose(lines);
  int status = 0;
  ::waitpid(console, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the walk ended before the kill";

  std::optional<link::Heartbeat> hold;
  while (!hold && secondsSince(killed) < link_timeout_s + 3.0)
    for (const auto& t : monitor.receive(50ms))
      if (const auto* h = std::get_if<link::Heartbeat>(&t.body); h && h->holding) hold = *h;
  ASSERT_TRUE(hold) << "ambler-sim did not hold after the console died";
  // The hold comes a link timeout after the last command, which may have
  // been sent a little before the kill.
  EXPECT_LT(secondsSince(killed), link_timeout_s + 1.0);
  EXPECT_EQ(hold->hold_reason.rfind("link lost", 0), 0u) << hold->hold_reason;

  const auto traffic = readTraffic(log);
  for (const auto sequence : acked) {
    EXPECT_TRUE(traffic.commands.count(sequence)) << "command " << sequence << " lost";
    EXPECT_TRUE(traffic.acks.count(sequence)) << "ack of " << sequence << " lost";
  }
}

// A console (ambler-cli drive) killed with SIGKILL while its body move is
// under way on a rover whose moves take their time (a body move of the
// first step about 8 s). Another console joins once the dead one's command
// authority has lapsed: the rover's state, kept on DDS for late joiners,
// says a move is under way, and the new console scans only after the
// rover reports its end (before then the rover would refuse the scan),
// and proposes its first step from there.
TEST(ExecutiveOverDds, AConsoleJoiningWhileAMoveIsUnderWayScansAfterItsEnd) {
  TempDir dir;
  const auto domain = testDomain();
  SimProcess sim(dir, domain, 1.0, 0.8);
  link::dds::DdsLink monitor(domain, 1);
  ASSERT_TRUE(killADriveMidBodyMove(dir, domain)) << "the first console did not move the rover";
  bool lapsed = false;  // the rover holds for the lost link, and nobody holds authority
  const auto killed = Clock::now();
  while (!lapsed && secondsSince(killed) < 10)
    for (const auto& t : monitor.receive(50ms))
      if (const auto* h = std::get_if<link::Heartbeat>(&t.body))
        lapsed = h->holding && h->authority.empty();
  ASSERT_TRUE(lapsed) << "the dead console's authority did not lapse";

  link::dds::DdsLink dds(domain, 1);
  link::CommandSigner signer(alice());
  ApprovalGate gate([](const missionlog::Decision&) {});
  ExecutiveOptions options;
  options.heartbeat_period_s = 0.25;  // well under the rover's link timeout
  WalkExecutive executive(dds, signer, gate, ground(), options);
  const auto pollUntil = [&](auto done, double limit_s) {
    const auto t0 = Clock::now();
    while (!done() && secondsSince(t0) < limit_s) executive.poll(link::utcNowS(), 50ms);
  };
  executive.start(link::utcNowS(), true);
  pollUntil([&] { return executive.phase() != Phase::kConnecting; }, 10);
  ASSERT_EQ(executive.phase(), Phase::kAwaitingMoveEnd) << executive.events().back().what;
  pollUntil([&] { return executive.phase() != Phase::kAwaitingMoveEnd; }, 30);
  EXPECT_EQ(executive.phase(), Phase::kScanning) << executive.events().back().what;
  pollUntil([&] { return gate.pending() || executive.phase() == Phase::kSuspended; }, 30);
  EXPECT_TRUE(gate.pending()) << executive.suspendedBecause();
  for (const auto& e : executive.events())
    EXPECT_EQ(e.what.find("refused"), std::string::npos) << e.what;
}

// The same with the joining console an `ambler-cli drive --resume`, which
// reads the rover's state while it waits for command authority, before its
// walk begins: the walk is handed that state, so it too waits for the move
// under way to end, says so, and its scan is accepted.
TEST(ExecutiveOverDds, ADriveJoiningWhileAMoveIsUnderWayScansAfterItsEnd) {
  TempDir dir;
  const auto domain = testDomain();
  SimProcess sim(dir, domain, 2.0, 0.8);
  ASSERT_TRUE(killADriveMidBodyMove(dir, domain)) << "the first console did not move the rover";
  const auto [second, lines] =
      startDrive(dir, domain, dir / "second.db", {"--steps", "1", "--auto-approve", "--resume"});
  ASSERT_GE(second, 0);
  std::vector<std::string> events;
  std::optional<nlohmann::json> scan_ack;
  char line[4096];
  const auto start = Clock::now();
  while (!scan_ack && secondsSince(start) < 60 && std::fgets(line, sizeof line, lines)) {
    const auto j = nlohmann::json::parse(line);
    if (j.contains("event")) events.push_back(j["event"]);
    if (j.contains("ack") && j.value("command", "") == "AcquireScan") scan_ack = j;
  }
  ::kill(second, SIGKILL);
  std::fclose(lines);
  ::waitpid(second, nullptr, 0);
  ASSERT_TRUE(scan_ack) << "the second console sent no scan";
  EXPECT_TRUE(scan_ack->value("accepted", false)) << scan_ack->dump();
  const auto said = [&](const std::string& what) {
    return std::find(events.begin(), events.end(), what) != events.end();
  };
  EXPECT_TRUE(said("connected: the rover reports a move under way; the scan waits for its end"));
  EXPECT_TRUE(said("the rover reports the move under way ended"));
}

// A rover that reports its state and heartbeat but answers no command: the
// console (ambler-cli drive) suspends at its ack timeout, says which
// commands it still waits for, and at its own timeout names them again.
TEST(ExecutiveOverDds, AConsoleWhoseCommandsAreNeverAnsweredSaysWhichItWaitsFor) {
  TempDir dir;
  const auto domain = testDomain();
  rover::SimulatedRoverOptions rover_options;
  rover_options.operators = {alice()};
  rover::SimulatedRover rover(simulator(), rover_options);
  link::dds::RoverEndpoint endpoint(domain, 1);
  std::atomic<bool> stop{false};
  std::thread mute([&] {
    while (!stop) {
      for (const auto& t : rover.state(link::utcNowS())) endpoint.publish(t);
      endpoint.publish(rover.heartbeat(link::utcNowS()));
      (void)endpoint.takeCommands(100ms);  // taken, never answered
    }
  });
  // Past the ack timeout (10 s) with room for a slow start.
  const auto [console, in] = startDrive(dir, domain, dir / "mission.db",
                                        {"--steps", "1", "--auto-approve", "--timeout", "20"});
  ASSERT_GE(console, 0);
  std::vector<nlohmann::json> lines;
  for (char line[4096]; std::fgets(line, sizeof line, in);)
    lines.push_back(nlohmann::json::parse(line, nullptr, false));
  std::fclose(in);
  int status = 0;
  ::waitpid(console, &status, 0);
  stop = true;
  mute.join();

  ASSERT_FALSE(lines.empty());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 2) << lines.back();
  const auto summary = lines.back();
  EXPECT_EQ(summary.value("stopped", ""), "suspended") << summary;
  // The scan, and the Hold the suspension sent.
  EXPECT_EQ(summary.value("unanswered", -1), 2) << summary;
  ASSERT_EQ(summary["unanswered_commands"].size(), 2u) << summary;
  const std::string scan = summary["unanswered_commands"][0],
                    hold = summary["unanswered_commands"][1];
  EXPECT_EQ(scan.rfind("AcquireScan ", 0), 0u) << scan;
  EXPECT_EQ(hold.rfind("Hold ", 0), 0u) << hold;
  const auto waiting = std::find_if(lines.begin(), lines.end(), [](const nlohmann::json& j) {
    return j.value("event", "").rfind("stopped (suspended); waiting for", 0) == 0;
  });
  ASSERT_NE(waiting, lines.end());
  EXPECT_EQ((*waiting)["event"],
            "stopped (suspended); waiting for the answers to " + scan + ", " + hold);
}

// The rover's process killed with SIGKILL mid-walk: the executive does not
// throw; once the link can no longer carry a command it says so, the walk
// is suspended and nothing pending is left to go out; when a rover is
// heard again and the operator resumes, the step is scanned and planned
// afresh and the walk goes on.
TEST(ExecutiveOverDds, ARoverKilledMidWalkSuspendsTheWalkUntilHeardAgainAndResumed) {
  TempDir dir;
  const auto domain = testDomain();
  auto sim = std::make_unique<SimProcess>(dir, domain, 3.0);
  link::dds::DdsLink dds(domain, 1);
  link::CommandSigner signer(alice());
  ApprovalGate gate([](const missionlog::Decision&) {});
  gate.setMode(ApprovalMode::kAutoApprove);
  ExecutiveOptions options;
  options.steps = 30;
  WalkExecutive executive(dds, signer, gate, ground(), options);
  const auto pollUntil = [&](auto done, double limit_s) {
    const auto t0 = Clock::now();
    while (!done() && secondsSince(t0) < limit_s) executive.poll(link::utcNowS(), 50ms);
  };
  executive.start(link::utcNowS());
  pollUntil([&] { return executive.stepsDone() >= 2; }, 60);
  ASSERT_GE(executive.stepsDone(), 2) << executive.events().back().what;

  sim->stop(SIGKILL);
  const int steps_before = executive.stepsDone();
  // DDS notices a vanished participant when its lease (10 s) runs out.
  EXPECT_NO_THROW(pollUntil([&] { return executive.linkLost().has_value(); }, 30));
  ASSERT_TRUE(executive.linkLost().has_value());
  executive.poll(link::utcNowS(), 0ms);
  EXPECT_EQ(executive.phase(), Phase::kSuspended);
  EXPECT_FALSE(gate.pending());
  const auto& events = executive.events();
  EXPECT_TRUE(std::any_of(events.begin(), events.end(), [](const ExecutiveEvent& e) {
    return e.what.rfind("link lost", 0) == 0;
  }));

  sim = std::make_unique<SimProcess>(dir, domain, 3.0);
  pollUntil([&] { return !executive.linkLost(); }, 30);
  ASSERT_FALSE(executive.linkLost()) << "the restarted rover was not heard";
  EXPECT_EQ(executive.phase(), Phase::kSuspended);
  executive.resume(link::utcNowS());
  pollUntil([&] { return executive.stepsDone() > steps_before; }, 60);
  EXPECT_GT(executive.stepsDone(), steps_before) << executive.events().back().what;
}

}  // namespace
}  // namespace ambler::executive
