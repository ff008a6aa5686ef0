// ambler-cli eval link: how fast the link is end to end. It starts
// ambler-sim on a private DDS domain on loopback and, as a console would,
// signs each command, logs it, sends it, and waits for the acknowledgement,
// which it logs too; then it asks for range images back to back.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>
#include <algorithm>
#include <fstream>
#include <memory>

#include "cli/Arguments.h"
#include "cli/Commands.h"
#include "link/Signing.h"
#include "link/dds/DdsMessages.h"
#include "missionlog/ReplayLinks.h"

namespace ambler::cli {

namespace {

using Clock = std::chrono::steady_clock;

struct EvalLinkArgs {
  std::uint32_t domain = 230;
  int round_trips = 500;
  int scans = 20;
  std::string sim;
  int cpu_load = 0;
  bool json = false;
};

// Processes that keep a core busy each, at the same priority as this one,
// for as long as the measurement: an operator's laptop is rarely idle.
class CpuLoad {
 public:
  explicit CpuLoad(int processes) {
    for (int i = 0; i < processes; ++i) {
      const pid_t pid = ::fork();
      if (pid < 0) throw std::runtime_error("cannot start a load process");
      if (pid == 0) {
        volatile unsigned long spin = 0;
        for (;;) spin = spin + 1;
      }
      pids_.push_back(pid);
    }
  }
  ~CpuLoad() {
    for (const pid_t pid : pids_) ::kill(pid, SIGKILL), ::waitpid(pid, nullptr, 0);
  }
  CpuLoad(const CpuLoad&) = delete;
  CpuLoad& operator=(const CpuLoad&) = delete;

 private:
  std::vector<pid_t> pids_;
};

// ambler-sim as a child process, stopped with the evaluation.
class SimChild {
 public:
  SimChild(const std::string& program, std::uint32_t domain, const std::filesystem::path& keys) {
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("cannot start " + program);
    if (pid_ == 0) {
      const int null = ::open("/dev/null", O_WRONLY);
      ::dup2(null, STDOUT_FILENO);
      const std::string d = std::to_string(domain);
      ::execl(program.c_str(), program.c_str(), "--domain", d.c_str(), "--keys", keys.c_str(),
              "--duration", "600", static_cast<char*>(nullptr));
      ::_exit(127);
    }
  }
  ~SimChild() {
    ::kill(pid_, SIGTERM);
    ::waitpid(pid_, nullptr, 0);
  }

 private:
  pid_t pid_ = -1;
};

std::string simProgram(const std::string& given) {
  if (!given.empty()) return given;
  return (std::filesystem::canonical("/proc/self/exe").parent_path() / "ambler-sim").string();
}

double percentile(std::vector<double> values, double p) {
  std::sort(values.begin(), values.end());
  const auto i =
      std::size_t(std::clamp(p * double(values.size() - 1), 0.0, double(values.size() - 1)) + 0.5);
  return values[i];
}

// Receives until `done` says so; throws after `limit` without it.
template <typename Done>
void receiveUntil(link::Link& link, Done&& done, std::chrono::seconds limit, const char* what) {
  const auto start = Clock::now();
  while (Clock::now() - start < limit)
    for (const auto& t : link.receive(std::chrono::milliseconds(20)))
      if (done(t)) return;
  throw std::runtime_error(std::string("ambler-sim did not answer: ") + what);
}

bool ackOf(const link::Telemetry& t, std::uint64_t sequence) {
  const auto* a = std::get_if<link::CommandAck>(&t.body);
  return a && a->sequence == sequence;
}

nlohmann::json evalLink(const EvalLinkArgs& a) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("ambler-eval-link-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const link::OperatorKey key{"eval", std::vector<std::uint8_t>(32, 0x5a)};
  std::string hex;
  for (std::size_t i = 0; i < key.key.size(); ++i) hex += "5a";
  std::ofstream(dir / "keys.json")
      << R"({"operators": [{"operator": "eval", "key_hex": ")" << hex << R"("}]})";
  std::vector<double> round_trip_ms;
  double images_per_s = 0.0, image_kb = 0.0;
  {
    SimChild sim(simProgram(a.sim), a.domain, dir / "keys.json");
    const CpuLoad load(a.cpu_load);
    link::dds::DdsLink dds(a.domain, 1);
    missionlog::MissionLog log(dir / "mission.db", "eval link");
    missionlog::RecordingLink link(dds, log);
    link::CommandSigner signer(key);
    receiveUntil(
        link, [](const auto& t) { return std::holds_alternative<link::BodyState>(t.body); },
        std::chrono::seconds(20), "no state within 20 s");
    auto roundTrip = [&](link::CommandBody body) {
      const link::Command c = signer.command(1, std::move(body));
      link.send(c);
      receiveUntil(
          link, [&](const auto& t) { return ackOf(t, c.sequence); }, std::chrono::seconds(10),
          "no acknowledgement within 10 s");
    };
    // Resume is verified, executed and acknowledged but moves nothing, so
    // the figure is the link's, not the simulated joints'.
    for (int i = 0; i < a.round_trips; ++i) {
      const auto start = Clock::now();
      roundTrip(link::Resume{});
      round_trip_ms.push_back(millisecondsSince(start));
    }
    const auto start = Clock::now();
    for (int i = 0; i < a.scans; ++i) {
      link.send(signer.command(1, link::AcquireScan{}));
      receiveUntil(
          link,
          [&](const auto& t) {
            const auto* image = std::get_if<sensor::RangeImage>(&t.body);
            if (image) image_kb = double(image->range.size()) * 4 / 1024;
            return image != nullptr;
          },
          std::chrono::seconds(30), "no range image within 30 s");
    }
    images_per_s = a.scans / (millisecondsSince(start) / 1000);
  }
  std::filesystem::remove_all(dir);
  const nlohmann::json report{
      {"round_trip_ms",
       {{"p50", percentile(round_trip_ms, 0.5)},
        {"p99", percentile(round_trip_ms, 0.99)},
        {"max", percentile(round_trip_ms, 1.0)},
        {"n", round_trip_ms.size()}}},
      {"round_trip_includes",
       "HMAC-SHA256 signing, mission log write of the command and of the ack (SQLite WAL, "
       "synchronous=FULL, one commit per batch received), DDS both ways on loopback, "
       "verification in ambler-sim"},
      {"cpu_load_processes", a.cpu_load},
      {"range_images_per_s", images_per_s},
      {"range_image_kb", image_kb},
      {"range_images_include", "ray casting in ambler-sim, DDS transfer, mission log write"},
      {"domain", a.domain}};
  return report;
}

}  // namespace

void addEvalLink(CLI::App& eval, Evaluations& all) {
  all.push_back({"link", [] { return evalLink(EvalLinkArgs{}); }});
  auto args = std::make_shared<EvalLinkArgs>();
  auto* cmd = eval.add_subcommand(
      "link", "Command round trip and range-image rate through DDS to ambler-sim and back");
  cmd->add_option("--domain", args->domain, "private DDS domain for the measurement")
      ->check(CLI::Range(0, 232))
      ->capture_default_str();
  cmd->add_option("--round-trips", args->round_trips, "commands to time")
      ->check(CLI::Range(10, 100000))
      ->capture_default_str();
  cmd->add_option("--scans", args->scans, "range images to ask for")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  cmd->add_option("--sim", args->sim, "ambler-sim to start (default: next to ambler-cli)");
  cmd->add_option("--cpu-load", args->cpu_load,
                  "CPU-bound processes (same priority) to run during the measurement")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  cmd->add_flag("--json", args->json, "print JSON (the only output format)");
  cmd->callback([args] { printJson(evalLink(*args)); });
}

}  // namespace ambler::cli
