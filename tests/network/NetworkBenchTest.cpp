// The rover link over a network with delay, loss and outages: ambler-sim
// in a "rover" namespace, consoles (ambler-cli drive) in two "ground"
// namespaces, DDS by unicast peers through udp-relay, which makes each
// link profile (namespaces.sh draws the network). Needs root for the
// namespaces; every process is bounded in time and the namespaces go with
// the test.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "TempDir.h"
#include "link/Codec.h"
#include "link/Signing.h"
#include "missionlog/MissionLog.h"

namespace ambler {
namespace {

using Json = nlohmann::json;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

struct Profile {
  std::string name;
  double delay_ms = 0, jitter_ms = 0, loss = 0;
};

void PrintTo(const Profile& p, std::ostream* out) { *out << p.name; }

const Profile kLan{"lan", 1, 0, 0};
const Profile kFieldRadio{"field_radio", 50, 20, 0.05};
const Profile kLunarRelay{"lunar_relay", 1300, 0, 0.01};

// A program in a namespace, its standard output and error in a file.
class Process {
 public:
  Process(const std::string& ns, const fs::path& dds_config, std::vector<std::string> argv,
          fs::path out)
      : out_(std::move(out)) {
    std::vector<std::string> full = {"ip", "netns", "exec", ns, "env"};
    if (!dds_config.empty()) full.push_back("CYCLONEDDS_URI=file://" + dds_config.string());
    full.insert(full.end(), argv.begin(), argv.end());
    pid_ = ::fork();
    if (pid_ == 0) {
      const int fd = ::open(out_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(fd, 1), ::dup2(fd, 2);
      std::vector<char*> args;
      for (auto& a : full) args.push_back(a.data());
      args.push_back(nullptr);
      ::execvp("ip", args.data());
      ::_exit(127);
    }
  }
  ~Process() {
    if (!exited_) ::kill(pid_, SIGKILL), ::waitpid(pid_, nullptr, 0);
  }
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;

  void signal(int sig) const { ::kill(pid_, sig); }
  // The exit code, or none if still running after `limit`.
  std::optional<int> wait(std::chrono::seconds limit) {
    const auto until = Clock::now() + limit;
    while (!exited_) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        exited_ = true, code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      } else if (Clock::now() > until) {
        return std::nullopt;
      } else {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    }
    return code_;
  }
  // Its JSON lines so far.
  std::vector<Json> lines() const {
    std::vector<Json> out;
    std::ifstream in(out_);
    for (std::string line; std::getline(in, line);)
      if (auto j = Json::parse(line, nullptr, false); !j.is_discarded() && j.is_object())
        out.push_back(std::move(j));
    return out;
  }
  std::string text() const {
    std::ifstream in(out_);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  // The first line `pred` accepts, waiting up to `limit`.
  std::optional<Json> waitFor(const std::function<bool(const Json&)>& pred,
                              std::chrono::seconds limit) {
    const auto until = Clock::now() + limit;
    do {
      for (const auto& j : lines())
        if (pred(j)) return j;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    } while (Clock::now() < until);
    return std::nullopt;
  }
  Json last() const {
    const auto all = lines();
    return all.empty() ? Json() : all.back();
  }

 private:
  fs::path out_;
  pid_t pid_ = -1;
  bool exited_ = false;
  int code_ = -1;
};

bool ackOf(const Json& j, const std::string& command, bool accepted = true) {
  return j.contains("ack") && j.value("command", "") == command &&
         j.value("accepted", !accepted) == accepted;
}

long count(const std::vector<Json>& lines, const std::function<bool(const Json&)>& pred) {
  return std::count_if(lines.begin(), lines.end(), pred);
}

// The namespaces, keys, DDS configurations and the relay of one test.
class NetworkBench : public testing::Test {
 protected:
  void SetUp() override {
    if (::geteuid() != 0) GTEST_SKIP() << "network namespaces need root (CI runs as root)";
    prefix_ = "amb" + std::to_string(::getpid() % 100000);
    ASSERT_EQ(std::system(("bash " NAMESPACES_SCRIPT " up " + prefix_).c_str()), 0);
    alice_ = link::newOperatorKey("alice"), bob_ = link::newOperatorKey("bob");
    link::writeOperatorKey(dir_ / "alice.key", alice_);
    link::writeOperatorKey(dir_ / "bob.key", bob_);
    std::ofstream(dir_ / "operators.json") << Json{
        {"operators",
         {{{"operator", "alice"}, {"key_hex", link::keyHex(alice_)}},
          {{"operator", "bob"},
           {"key_hex", link::keyHex(bob_)}}}}}.dump();
    writeDdsConfig("rover", "rv", "10.77.9.9", {"10.77.8.1", "10.77.8.2"});
    writeDdsConfig("ground-a", "ga", "10.77.8.1", {"10.77.9.9"});
    writeDdsConfig("ground-b", "gb", "10.77.8.2", {"10.77.9.9"});
  }
  void TearDown() override {
    processes_.clear();
    if (!prefix_.empty()) std::system(("bash " NAMESPACES_SCRIPT " down " + prefix_).c_str());
  }

  // Unicast peers, no multicast, as docs/dds.md tells a real user; each
  // side knows the other by its public address, which the relay holds. A
  // lease of 60 s rides out the outages a radio link has.
  void writeDdsConfig(const std::string& node, const std::string& iface,
                      const std::string& external, const std::vector<std::string>& peers) {
    std::ostringstream xml;
    xml << R"(<CycloneDDS xmlns="https://cdds.io/config"><Domain Id="any"><General>)"
        << R"(<Interfaces><NetworkInterface name=")" << iface
        << R"(" multicast="false"/></Interfaces><AllowMulticast>false</AllowMulticast>)"
        << "<ExternalNetworkAddress>" << external << "</ExternalNetworkAddress></General>"
        << "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
        << "<MaxAutoParticipantIndex>9</MaxAutoParticipantIndex><Peers>";
    for (const auto& p : peers) xml << "<Peer address=\"" << p << "\"/>";
    xml << "</Peers><LeaseDuration>60 s</LeaseDuration></Discovery></Domain></CycloneDDS>";
    std::ofstream(dir_ / (node + ".xml")) << xml.str();
  }

  Process& start(const std::string& node, std::vector<std::string> argv, const std::string& name) {
    processes_.push_back(std::make_unique<Process>(
        prefix_ + "-" + node, node == "relay" ? fs::path() : dir_ / (node + ".xml"),
        std::move(argv), dir_ / (name + ".out")));
    return *processes_.back();
  }

  Process& relay(const Profile& p) {
    auto& r =
        start("relay",
              {AMBLER_RELAY, "--path", "10.77.1.2,10.77.8.1,10.77.9.9,10.77.2.2", "--path",
               "10.77.3.2,10.77.8.2,10.77.9.9,10.77.2.2", "--ports", "7400-7440", "--delay-ms",
               std::to_string(p.delay_ms), "--jitter-ms", std::to_string(p.jitter_ms), "--loss",
               std::to_string(p.loss), "--seed", "7", "--duration", "900"},
              "relay");
    EXPECT_TRUE(r.waitFor([](const Json& j) { return j.value("relay", "") == "ready"; },
                          std::chrono::seconds(10)));
    return r;
  }
  Process& rover() {
    auto& sim = start(
        "rover", {AMBLER_SIM, "--keys", (dir_ / "operators.json").string(), "--duration", "900"},
        "sim");
    EXPECT_TRUE(sim.waitFor([](const Json& j) { return j.value("ambler_sim", "") == "ready"; },
                            std::chrono::seconds(20)));
    return sim;
  }
  // A console: ambler-cli drive with a key (alice at ground-a, bob at
  // ground-b) or none (--watch), logging to NAME.db.
  Process& console(const std::string& node, const std::string& name,
                   std::vector<std::string> options) {
    std::vector<std::string> argv = {
        AMBLER_CLI, "drive", "--log", (dir_ / (name + ".db")).string(), "--timeout", "600"};
    argv.insert(argv.end(), options.begin(), options.end());
    return start(node, argv, name);
  }
  // The relay on `profile`, the rover, a console watching at ground-b and
  // alice walking 10 steps at ground-a.
  struct Walk {
    Process &relay, &rover, &watcher, &walker;
  };
  Walk watchedWalk(const Profile& profile) {
    auto& r = relay(profile);
    auto& sim = rover();
    auto& watcher = console("ground-b", "watcher", {"--watch"});
    // A reader that matches late gets only the last 64 acknowledgements:
    // the watcher must have found the rover before the first command, or
    // a walk's early answers may be gone by then.
    EXPECT_TRUE(watcher.waitFor([](const Json& j) { return j.value("link", "") == "fresh"; },
                                std::chrono::seconds(60)));
    auto options = key("alice");
    options.insert(options.end(), {"--steps", "10", "--auto-approve"});
    return {r, sim, watcher, console("ground-a", "walker", options)};
  }
  std::vector<std::string> key(const std::string& who) {
    return {"--key", (dir_ / (who + ".key")).string()};
  }

  // The messages of type T a console's mission log received.
  template <typename T>
  std::vector<T> received(const std::string& name) const {
    missionlog::MissionLogReader log(dir_ / (name + ".db"));
    std::vector<T> out;
    for (const auto& m : log.messages(-1e300, 1e300))
      if (m.direction == missionlog::Direction::kFromRover) {
        const auto message = link::decodeTelemetry(m.payload);
        if (const auto* t = std::get_if<T>(&message.body)) out.push_back(*t);
      }
    return out;
  }
  // The acknowledgements in a mission log, as "console#sequence: accepted".
  std::set<std::string> acksIn(const std::string& name) const {
    std::set<std::string> acks;
    for (const auto& a : received<link::CommandAck>(name))
      acks.insert(link::consoleName(a.operator_id, a.console_id) + "#" +
                  std::to_string(a.sequence) + (a.accepted ? ": accepted" : ": refused"));
    return acks;
  }
  // The consoles a log saw hold command authority, in order.
  std::vector<std::string> authorityIn(const std::string& name) const {
    std::vector<std::string> holders;
    for (const auto& h : received<link::Heartbeat>(name))
      if (holders.empty() || holders.back() != h.authority) holders.push_back(h.authority);
    return holders;
  }

  TempDir dir_;
  std::string prefix_;
  link::OperatorKey alice_, bob_;
  std::vector<std::unique_ptr<Process>> processes_;
};

// Every command answered, in both consoles' logs, executed once.
void expectEveryCommandAnsweredOnce(const Json& summary, const Json& sim_stopped,
                                    const std::vector<Json>& drive_lines) {
  EXPECT_EQ(summary.value("unanswered", -1), 0) << summary;
  for (const std::string type : {"LegMove", "BodyMove", "AcquireScan"}) {
    const long accepted = count(drive_lines, [&](const Json& j) { return ackOf(j, type); });
    EXPECT_EQ(sim_stopped["executed"].value(type, 0L), accepted) << type << ": " << sim_stopped;
  }
}

class ProfileWalk : public NetworkBench, public testing::WithParamInterface<Profile> {};

TEST_P(ProfileWalk, TenStepsWithApprovalsCompleteAndEveryAckIsInBothConsolesLogs) {
  const Profile profile = GetParam();
  auto [r, sim, watcher, walker] = watchedWalk(profile);
  ASSERT_EQ(walker.wait(std::chrono::seconds(600)), std::optional<int>(0)) << walker.text();
  const Json summary = walker.last();
  EXPECT_EQ(summary.value("steps_done", 0), 10) << summary;
  EXPECT_EQ(summary.value("refused", -1), 0) << summary;
  std::this_thread::sleep_for(std::chrono::duration<double>(3 * profile.delay_ms / 1000 + 1));
  watcher.signal(SIGTERM);
  ASSERT_EQ(watcher.wait(std::chrono::seconds(30)), std::optional<int>(0)) << watcher.text();
  sim.signal(SIGTERM);
  ASSERT_EQ(sim.wait(std::chrono::seconds(30)), std::optional<int>(0)) << sim.text();
  expectEveryCommandAnsweredOnce(summary, sim.last(), walker.lines());

  const auto walker_acks = acksIn("walker"), watcher_acks = acksIn("watcher");
  EXPECT_EQ(long(walker_acks.size()), summary.value("commands_sent", 0L));
  for (const auto& ack : walker_acks) EXPECT_TRUE(watcher_acks.count(ack)) << ack;
  r.signal(SIGTERM);
  r.wait(std::chrono::seconds(10));
  // The figures of the README's table.
  std::cout << "NETWORK_BENCH "
            << Json{{"profile", profile.name},
                    {"steps", summary["steps_done"]},
                    {"duration_s", summary["duration_s"]},
                    {"round_trip_s", summary["round_trip_s"]},
                    {"approval_to_motion_s", summary["approval_to_motion_s"]},
                    {"commands", summary["commands_sent"]},
                    {"relay", r.last()}}
            << std::endl;
}

INSTANTIATE_TEST_SUITE_P(Profiles, ProfileWalk, testing::Values(kLan, kFieldRadio, kLunarRelay),
                         [](const auto& info) { return info.param.name; });

// Cuts the relay for `seconds` once the walker's first step has moved.
void outageMidWalk(Process& relay, Process& walker, int seconds) {
  ASSERT_TRUE(walker.waitFor([](const Json& j) { return ackOf(j, "BodyMove"); },
                             std::chrono::seconds(120)));
  std::this_thread::sleep_for(std::chrono::seconds(1));
  relay.signal(SIGUSR1);
  std::this_thread::sleep_for(std::chrono::seconds(seconds));
  relay.signal(SIGUSR2);
}

// Shorter than the rover's link timeout: DDS resends what was lost, nobody
// holds, the walk goes on.
TEST_F(NetworkBench, ATwoSecondOutageIsRiddenOutWithoutAHold) {
  auto [r, sim, watcher, walker] = watchedWalk(kFieldRadio);
  outageMidWalk(r, walker, 2);
  ASSERT_EQ(walker.wait(std::chrono::seconds(120)), std::optional<int>(0)) << walker.text();
  EXPECT_EQ(walker.last().value("steps_done", 0), 10);
  EXPECT_EQ(walker.last().value("unanswered", -1), 0);
  EXPECT_EQ(sim.text().find("holds"), std::string::npos) << sim.text();
  r.signal(SIGTERM);
  r.wait(std::chrono::seconds(10));
  EXPECT_GT(r.last().value("outage_dropped", 0), 0) << r.text();  // there was one
}

class LongOutage : public NetworkBench, public testing::WithParamInterface<int> {};

TEST_P(LongOutage, MidWalkHoldsTheRoverUntilAnExplicitResume) {
  auto [r, sim, watcher, walker] = watchedWalk(kFieldRadio);
  outageMidWalk(r, walker, GetParam());

  // The walker says the link is stale within the rover's timeout (3 s),
  // and stops when it hears that the rover held.
  ASSERT_EQ(walker.wait(std::chrono::seconds(120)), std::optional<int>(2)) << walker.text();
  EXPECT_EQ(walker.last().value("stopped", ""), "suspended");
  const auto stale = walker.waitFor(
      [](const Json& j) { return j.value("link", "") == "stale" && j.value("t_s", 0.0) > 1; },
      std::chrono::seconds(1));
  ASSERT_TRUE(stale) << walker.text();
  EXPECT_LE(stale->value("age_s", 99.0), 3.5) << *stale;
  EXPECT_TRUE(watcher.waitFor([](const Json& j) { return j.value("link", "") == "stale"; },
                              std::chrono::seconds(1)));
  EXPECT_NE(sim.text().find("holds: link lost"), std::string::npos) << sim.text();
  const auto held = walker.waitFor(
      [](const Json& j) {
        return j.value("event", "").find("rover holds: link lost") != std::string::npos;
      },
      std::chrono::seconds(1));
  EXPECT_TRUE(held) << walker.text();
  const int done = walker.last().value("steps_done", 0);
  EXPECT_GE(done, 1);
  EXPECT_LT(done, 10);
  // What was in flight reached the rover after the outage, held: refused.
  for (const auto& j : walker.lines())
    if (j.contains("ack") && !j.value("accepted", true)) {
      std::cout << "REFUSED_AFTER_OUTAGE " << j << std::endl;
      const auto reason = j.value("reason", "");
      EXPECT_TRUE(reason.find("holding") != std::string::npos ||
                  reason.find("validity window") != std::string::npos)
          << j;
    }

  // The operator resumes explicitly; the walk goes on to 10 steps.
  auto resume_opts = key("alice");
  resume_opts.insert(resume_opts.end(),
                     {"--steps", std::to_string(10 - done), "--auto-approve", "--resume"});
  auto& resumed = console("ground-a", "walker", resume_opts);
  // The console's own lines last, where a log cut in its middle keeps them.
  ASSERT_EQ(resumed.wait(std::chrono::seconds(300)), std::optional<int>(0))
      << "rover:\n"
      << sim.text() << "\nresumed console:\n"
      << resumed.text();
  EXPECT_EQ(resumed.last().value("steps_done", 0), 10 - done);
  EXPECT_EQ(resumed.last().value("unanswered", -1), 0);
  std::this_thread::sleep_for(std::chrono::seconds(1));
  watcher.signal(SIGTERM);
  watcher.wait(std::chrono::seconds(30));
  // Nothing lost: every acknowledgement either console run got is in the
  // log, and the watcher's log has them all.
  const auto walker_acks = acksIn("walker"), watcher_acks = acksIn("watcher");
  for (const auto& ack : walker_acks) EXPECT_TRUE(watcher_acks.count(ack)) << ack;
  EXPECT_EQ(walker.last().value("unanswered", -1) + resumed.last().value("unanswered", -1), 0)
      << walker.last() << resumed.last();
}

INSTANTIATE_TEST_SUITE_P(Outages, LongOutage, testing::Values(10, 30),
                         [](const auto& info) { return std::to_string(info.param) + "s"; });

TEST_F(NetworkBench, ACommandDelayedPastItsValidityWindowIsRefusedOnBoard) {
  relay({"slow", 400, 0, 0});
  auto& sim = rover();
  auto opts = key("alice");
  opts.insert(opts.end(), {"--steps", "1", "--auto-approve", "--validity", "0.3"});
  auto& walker = console("ground-a", "walker", opts);
  ASSERT_EQ(walker.wait(std::chrono::seconds(120)), std::optional<int>(2)) << walker.text();
  const auto refused = walker.waitFor([](const Json& j) { return ackOf(j, "AcquireScan", false); },
                                      std::chrono::seconds(1));
  ASSERT_TRUE(refused) << walker.text();
  EXPECT_NE(refused->value("reason", "").find("after its validity window closed"),
            std::string::npos)
      << *refused;
  EXPECT_NE(sim.text().find("refused AcquireScan"), std::string::npos) << sim.text();
  sim.signal(SIGTERM);
  ASSERT_EQ(sim.wait(std::chrono::seconds(30)), std::optional<int>(0));
  EXPECT_EQ(sim.last()["executed"].value("AcquireScan", 0), 0) << sim.last();
}

TEST_F(NetworkBench, OnlyTheConsoleInCommandMovesTheRoverAndAHandOverMidWalkIsLoggedOnBoth) {
  relay(kFieldRadio);
  auto& sim = rover();
  auto a_opts = key("alice");
  // Alice's walk is far longer than bob's discovery and request take (a
  // step is about 0.5 s), so the hand-over lands mid-walk however slow the
  // machine; she stops at the first step boundary after bob asks.
  a_opts.insert(a_opts.end(), {"--steps", "100", "--auto-approve", "--hand-over"});
  auto& alice = console("ground-a", "alice", a_opts);
  ASSERT_TRUE(alice.waitFor([](const Json& j) { return ackOf(j, "AcquireScan"); },
                            std::chrono::seconds(120)));

  // Bob without authority: his first command is refused, nothing moves.
  auto intruder_opts = key("bob");
  intruder_opts.insert(intruder_opts.end(), {"--steps", "1", "--auto-approve"});
  auto& intruder = console("ground-b", "intruder", intruder_opts);
  ASSERT_EQ(intruder.wait(std::chrono::seconds(120)), std::optional<int>(2)) << intruder.text();
  const auto refused = intruder.waitFor(
      [](const Json& j) { return ackOf(j, "AcquireScan", false); }, std::chrono::seconds(1));
  ASSERT_TRUE(refused) << intruder.text();
  EXPECT_NE(refused->value("reason", "").find("does not hold command authority"),
            std::string::npos);

  // Bob asks mid-walk; alice hands over between two steps; bob walks on.
  auto b_opts = key("bob");
  b_opts.insert(b_opts.end(), {"--steps", "3", "--auto-approve", "--take-over"});
  auto& bob = console("ground-b", "bob", b_opts);
  ASSERT_TRUE(
      bob.waitFor([](const Json& j) { return j.contains("authority"); }, std::chrono::seconds(60)));
  ASSERT_TRUE(alice.waitFor(
      [&](const Json&) {
        return count(alice.lines(), [](const Json& j) { return ackOf(j, "BodyMove"); }) >= 3;
      },
      std::chrono::seconds(120)));
  bob.signal(SIGUSR1);
  ASSERT_EQ(alice.wait(std::chrono::seconds(120)), std::optional<int>(0)) << alice.text();
  const std::string bob_console = bob.lines().front().value("console", "");
  EXPECT_EQ(alice.last().value("stopped", ""), "handed over to " + bob_console);
  const int alice_steps = alice.last().value("steps_done", 0);
  EXPECT_GE(alice_steps, 3);
  EXPECT_LT(alice_steps, 100);
  ASSERT_EQ(bob.wait(std::chrono::seconds(180)), std::optional<int>(0)) << bob.text();
  EXPECT_EQ(bob.last().value("steps_done", 0), 3);

  // Both logs show alice in command, then bob; and the hand-over's
  // acknowledgement.
  const std::string alice_console = alice.last().value("console", "");
  for (const std::string log : {"alice", "bob"}) {
    const auto holders = authorityIn(log);
    const auto a = std::find(holders.begin(), holders.end(), alice_console);
    ASSERT_NE(a, holders.end()) << log;
    EXPECT_NE(std::find(a, holders.end(), bob_console), holders.end()) << log;
  }
  const auto hand_over =
      alice.waitFor([](const Json& j) { return ackOf(j, "HandOver"); }, std::chrono::seconds(1));
  ASSERT_TRUE(hand_over) << alice.text();
  const std::string logged =
      alice_console + "#" + std::to_string(hand_over->value("ack", 0UL)) + ": accepted";
  EXPECT_TRUE(acksIn("alice").count(logged)) << logged;
  EXPECT_TRUE(acksIn("bob").count(logged)) << logged;
  sim.signal(SIGTERM);
  ASSERT_EQ(sim.wait(std::chrono::seconds(30)), std::optional<int>(0));
  EXPECT_NE(sim.text().find(alice_console + " handed command authority to " + bob_console),
            std::string::npos)
      << sim.text();
}

}  // namespace
}  // namespace ambler
