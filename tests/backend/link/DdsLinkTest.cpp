// The link over Cyclone DDS on loopback: a console and the simulated rover
// in this process, and ambler-sim as its own process. Each test process
// takes its own domain so that parallel ctest runs do not hear each other.
#include "link/dds/DdsMessages.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include "InstalledConfig.h"
#include "rover/RoverLoop.h"
#include "rover/SimulatedRover.h"

namespace ambler::link::dds {
namespace {

std::uint32_t testDomain() { return 20 + std::uint32_t(::getpid()) % 200; }

OperatorKey alice() { return {"alice", std::vector<std::uint8_t>(32, 7)}; }

using testing_config::ground;
using testing_config::simulator;

Command signedCommand(CommandBody body, CommandSigner& signer, std::uint32_t rover = 1) {
  Command c;
  c.rover_id = rover;
  c.body = std::move(body);
  signer.sign(c);
  return c;
}

// Collects telemetry until `done` says so or `limit` has passed. A time,
// not a count of receives: telemetry streams in, so receives return early.
template <typename Done>
std::vector<Telemetry> collect(Link& link, Done&& done,
                               std::chrono::milliseconds limit = std::chrono::seconds(30)) {
  std::vector<Telemetry> all;
  const auto until = std::chrono::steady_clock::now() + limit;
  while (!done(all) && std::chrono::steady_clock::now() < until)
    for (auto& t : link.receive(std::chrono::milliseconds(50))) all.push_back(std::move(t));
  return all;
}

template <typename T>
std::vector<T> only(const std::vector<Telemetry>& all) {
  std::vector<T> out;
  for (const auto& t : all)
    if (const auto* m = std::get_if<T>(&t.body)) out.push_back(*m);
  return out;
}

// The simulated rover serving DDS on a thread of this process.
class RoverThread {
 public:
  explicit RoverThread(std::uint32_t domain) : endpoint_(domain, 1) {
    rover::SimulatedRoverOptions options;
    options.operators = {alice()};
    options.scanned_area = {-6, -6, 6, 12};
    rover_ = std::make_unique<rover::SimulatedRover>(simulator(), options);
    thread_ = std::thread([this] {
      rover::RoverLoopIo io;
      io.receive = [this](std::chrono::milliseconds timeout) {
        std::vector<rover::Incoming> in;
        for (auto& r : endpoint_.takeCommands(std::min(timeout, std::chrono::milliseconds(50))))
          in.push_back({std::move(r.command), std::move(r.malformed)});
        return in;
      };
      io.publish = [this](const Telemetry& t) { endpoint_.publish(t); };
      io.stopping = [this] { return stop_.load(); };
      rover::runRoverLoop(*rover_, std::chrono::milliseconds(100), io);
    });
  }
  ~RoverThread() {
    stop_ = true;
    thread_.join();
  }

 private:
  RoverEndpoint endpoint_;
  std::unique_ptr<rover::SimulatedRover> rover_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

TEST(DdsLink, CommandsAndTelemetryCrossTheDomainInOrder) {
  const auto domain = testDomain();
  RoverThread rover(domain);
  DdsLink link(domain, 1);
  EXPECT_EQ(link.describe(), "DDS domain " + std::to_string(domain) + ", rover 1");
  // The rover's first state is there for a console that joins late. Each
  // message kind is its own topic, matched on its own: the body's state may
  // come before the legs'.
  auto all = collect(link, [](const auto& a) {
    std::set<int> legs;
    for (const auto& leg : only<LegState>(a)) legs.insert(leg.leg);
    return !only<BodyState>(a).empty() && legs.size() == std::size_t(gait::kLegCount);
  });
  ASSERT_FALSE(only<BodyState>(all).empty());
  const double start_y = only<BodyState>(all).back().y_m;
  // The feet carry the rover's weight (force sensors, simulated statics).
  double load_n = 0;
  std::map<int, double> last_load;
  for (const auto& leg : only<LegState>(all)) last_load[leg.leg] = leg.force_n;
  for (const auto& [leg, force] : last_load) load_n += force;
  EXPECT_EQ(last_load.size(), std::size_t(gait::kLegCount));
  EXPECT_NEAR(load_n, ground().model.mass_kg * 9.81, 1.0);

  CommandSigner signer(alice());
  link.send(signedCommand(BodyMove{0.0, 0.2, 0.0, 0.0}, signer));
  link.send(signedCommand(BodyMove{0.0, 0.2, 0.0, 0.0}, signer));
  link.send(signedCommand(AcquireScan{}, signer));
  Command unsigned_command;
  unsigned_command.rover_id = 1, unsigned_command.operator_id = "alice";
  unsigned_command.sequence = 99, unsigned_command.body = Hold{};
  link.send(unsigned_command);
  all = collect(link, [](const auto& a) {
    return only<CommandAck>(a).size() >= 4 && !only<sensor::RangeImage>(a).empty();
  });
  const auto acks = only<CommandAck>(all);
  ASSERT_EQ(acks.size(), 4u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(acks[i].accepted) << acks[i].reason;
    EXPECT_EQ(acks[i].sequence, std::uint64_t(i + 1));  // in the order sent
  }
  EXPECT_EQ(acks[3].reason, "unsigned command");
  const auto images = only<sensor::RangeImage>(all);
  ASSERT_EQ(images.size(), 1u);
  EXPECT_GT(images[0].returnCount(), images[0].rows() * images[0].cols() / 2);
  EXPECT_NEAR(only<BodyState>(all).back().y_m - start_y, 0.4, 0.03);
  EXPECT_EQ(link.dropped(), 0);
}

TEST(DdsLink, AStriperImageCrossesTheDomainWhole) {
  const auto domain = testDomain();
  RoverThread rover(domain);
  DdsLink link(domain, 1);
  collect(link, [](const auto& a) { return !only<BodyState>(a).empty(); });
  CommandSigner signer(alice());
  link.send(signedCommand(AcquireScan{ScanSensor::kLightStriper}, signer));
  const auto all =
      collect(link, [](const auto& a) { return !only<sensor::StriperImage>(a).empty(); });
  const auto images = only<sensor::StriperImage>(all);
  ASSERT_EQ(images.size(), 1u);
  const auto& image = images[0];
  EXPECT_EQ(image.rows(), 256);
  EXPECT_EQ(image.x.size(), 256u * 256u);
  EXPECT_EQ(sensor::findProblem(image), "");
  EXPECT_GT(image.pointCount(), 256 * 256 / 2);
  EXPECT_EQ(link.dropped(), 0);
}

// Discovery runs each way on its own: the rover may take a console's
// command (its reader matched) before its own acknowledgement writer has
// matched that console's reader. The answer must still arrive, in order.
TEST(DdsLink, AcknowledgementsWrittenBeforeAConsoleMatchedReachIt) {
  const auto domain = testDomain();
  RoverEndpoint rover(domain, 1);
  for (std::uint64_t sequence : {7, 8})
    rover.publish({1, 100.0 + double(sequence), CommandAck{"alice", 3, sequence, true, ""}});
  DdsLink late(domain, 1);
  const auto acks = only<CommandAck>(collect(
      late, [](const auto& a) { return only<CommandAck>(a).size() >= 2; },
      std::chrono::seconds(10)));
  ASSERT_EQ(acks.size(), 2u);
  EXPECT_EQ(acks[0].sequence, 7u);
  EXPECT_EQ(acks[1].sequence, 8u);
  EXPECT_EQ(acks[1].operator_id, "alice");
  EXPECT_TRUE(acks[1].accepted);
}

TEST(DdsLink, AnotherRoversTrafficIsNotSeen) {
  const auto domain = testDomain();
  RoverThread rover(domain);  // rover 1
  DdsLink other(domain, 2);
  const auto all = collect(
      other, [](const auto&) { return false; }, std::chrono::seconds(1));
  EXPECT_TRUE(all.empty());
}

// ambler-sim in its own process: a console signs, the simulator verifies.
// A real rover is reached through a Cyclone configuration of the operator's
// network (docs/dds.md); here one that names the loopback interface.
TEST(DdsLink, UsesTheConfigurationInCycloneddsUri) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("ambler-dds-" + std::to_string(::getpid()) + ".xml");
  std::ofstream(path) << R"(<CycloneDDS xmlns="https://cdds.io/config"><Domain Id="any">
  <General><Interfaces><NetworkInterface address="127.0.0.1" multicast="false"/></Interfaces>
    <AllowMulticast>false</AllowMulticast></General>
  <Discovery><Peers><Peer address="127.0.0.1"/></Peers></Discovery></Domain></CycloneDDS>)";
  ::setenv("CYCLONEDDS_URI", ("file://" + path.string()).c_str(), 1);
  const auto domain = testDomain();
  RoverThread rover(domain);
  DdsLink link(domain, 1);
  const auto all = collect(link, [](const auto& a) { return !only<BodyState>(a).empty(); });
  ::unsetenv("CYCLONEDDS_URI");
  std::filesystem::remove(path);
  EXPECT_FALSE(only<BodyState>(all).empty());
}

TEST(DdsLink, ABadCycloneddsUriIsNamedInTheError) {
  ::setenv("CYCLONEDDS_URI", "file:///nonexistent/ambler-dds.xml", 1);
  try {
    // Not a domain this process has joined (it keeps the first configuration).
    DdsLink link(testDomain() + 1, 1);
    FAIL() << "joined a domain without its configuration";
  } catch (const LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("CYCLONEDDS_URI=file:///nonexistent/ambler-dds.xml"),
              std::string::npos)
        << e.what();
  }
  ::unsetenv("CYCLONEDDS_URI");
}

TEST(AmblerSim, ServesASignedConsoleOverDds) {
  const auto domain = testDomain();
  const auto keys = std::filesystem::temp_directory_path() /
                    ("ambler_sim_keys_" + std::to_string(::getpid()) + ".json");
  std::string hex;
  for (int i = 0; i < 32; ++i) hex += "07";  // alice(): 32 bytes of 7
  std::ofstream(keys) << R"({"operators": [{"operator": "alice", "key_hex": ")" << hex << R"("}]})";
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const std::string d = std::to_string(domain);
    ::execl(AMBLER_SIM, AMBLER_SIM, "--domain", d.c_str(), "--keys", keys.c_str(), "--heartbeat-ms",
            "100", "--duration", "30", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  DdsLink link(domain, 1);
  auto all = collect(link, [](const auto& a) { return !only<Heartbeat>(a).empty(); });
  ASSERT_FALSE(only<Heartbeat>(all).empty()) << "no heartbeat from ambler-sim";
  CommandSigner signer(alice());
  link.send(signedCommand(BodyMove{0.0, 0.3, 0.0, 0.0}, signer));
  CommandSigner forger({"alice", std::vector<std::uint8_t>(32, 9)}, 2);
  link.send(signedCommand(BodyMove{0.0, 0.3, 0.0, 0.0}, forger));
  all = collect(link, [](const auto& a) { return only<CommandAck>(a).size() >= 2; });
  ::kill(child, SIGTERM);
  int status = 0;
  ::waitpid(child, &status, 0);
  std::filesystem::remove(keys);
  const auto acks = only<CommandAck>(all);
  ASSERT_EQ(acks.size(), 2u);
  EXPECT_TRUE(acks[0].accepted) << acks[0].reason;
  EXPECT_EQ(acks[1].reason, "bad signature for operator \"alice\"");
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "ambler-sim did not stop cleanly";
}

}  // namespace
}  // namespace ambler::link::dds
