// ambler-cli drive: a headless console. It walks a rover (or ambler-sim)
// over DDS with the executive in auto-approve mode, so every interlock
// still runs, and records everything in a mission log. It prints one JSON
// line per event and per acknowledgement, each after the log has it, then a
// summary.
#include <iostream>
#include <memory>

#include "cli/Arguments.h"
#include "cli/Commands.h"
#include "executive/WalkExecutive.h"
#include "gait/RoverConfig.h"
#include "link/dds/DdsMessages.h"
#include "missionlog/ReplayLinks.h"

namespace ambler::cli {

namespace {

struct DriveArgs {
  std::uint32_t domain = 0;
  std::uint32_t rover_id = 1;
  std::string key;
  std::string log;
  int steps = 5;
  bool auto_approve = false;
  bool resume = false;
  double timeout_s = 600.0;
};

void printLine(const nlohmann::json& line) { std::cout << line.dump() << std::endl; }

// Prints each acknowledgement as it comes out of the (recording) link.
class AckPrinter : public link::Link {
 public:
  explicit AckPrinter(link::Link& inner) : inner_(inner) {}
  void send(const link::Command& command) override {
    sent_[command.sequence] = link::typeName(command.body);
    inner_.send(command);
  }
  std::vector<link::Telemetry> receive(std::chrono::milliseconds timeout) override {
    auto in = inner_.receive(timeout);
    for (const auto& t : in)
      if (const auto* a = std::get_if<link::CommandAck>(&t.body))
        printLine({{"ack", a->sequence},
                   {"command", sent_.count(a->sequence) ? sent_[a->sequence] : "?"},
                   {"accepted", a->accepted},
                   {"reason", a->reason}});
    return in;
  }
  std::string describe() const override { return inner_.describe(); }

 private:
  link::Link& inner_;
  std::map<std::uint64_t, std::string> sent_;
};

int drive(const DriveArgs& a) {
  if (!a.auto_approve)
    throw std::invalid_argument(
        "drive has no operator to ask: pass --auto-approve (every interlock still runs) or "
        "approve steps in ambler-gs");
  const auto context = gait::readInstalledGaitContext();
  link::CommandSigner signer(link::readOperatorKey(a.key), missionlog::firstSequenceFromClock());
  missionlog::MissionLog log(a.log, "drive rover " + std::to_string(a.rover_id));
  link::dds::DdsLink dds(a.domain, a.rover_id);
  missionlog::RecordingLink recording(dds, log);
  link::LinkHealth health;
  link::WatchedLink watched(recording, health, missionlog::groundClockS);
  AckPrinter link(watched);
  executive::ApprovalGate gate([&](const missionlog::Decision& d) { log.record(d); });
  gate.setMode(executive::ApprovalMode::kAutoApprove);
  executive::ExecutiveOptions options;
  options.rover_id = a.rover_id;
  options.steps = a.steps;
  executive::WalkExecutive executive(link, signer, gate, context, options);
  executive.onProduct([&](double t, const std::string& kind, const std::string& parameters) {
    log.recordProduct(t, kind, parameters);
  });
  executive.onEvent([&](const executive::ExecutiveEvent& e) { log.recordEvent(e.time_s, e.what); });

  const double start_s = missionlog::groundClockS();
  std::size_t printed = 0;
  printLine({{"event", "waiting for the rover's state on " + link.describe()}, {"t_s", 0.0}});
  executive.start(start_s, a.resume);
  std::string stopped;
  bool stale = false;
  while (stopped.empty()) {
    const double now_s = missionlog::groundClockS();
    executive.poll(now_s, std::chrono::milliseconds(50));
    if (health.stale(now_s) != stale) {
      stale = !stale;
      const auto age = health.ageS(now_s);
      printLine({{"link", stale ? "stale" : "fresh"},
                 {"age_s", age ? nlohmann::json(*age) : nlohmann::json()},
                 {"t_s", now_s - start_s}});
    }
    for (; printed < executive.events().size(); ++printed)
      printLine({{"event", executive.events()[printed].what}, {"t_s", now_s - start_s}});
    const auto& pending = gate.pending();
    if (executive.phase() == executive::Phase::kDone)
      stopped = "done";
    else if (executive.phase() == executive::Phase::kSuspended)
      stopped = "suspended";
    else if (pending && !pending->interlocks.passed())
      stopped = "step fails interlock " + pending->interlocks.firstFailure() +
                "; no operator here to edit or reject it";
    else if (now_s - start_s > a.timeout_s)
      stopped = "timed out";
  }
  printLine({{"stopped", stopped},
             {"steps_done", executive.stepsDone()},
             {"steps_planned_ahead", executive.stepsPlannedAhead()},
             {"log", a.log},
             {"duration_s", missionlog::groundClockS() - start_s}});
  return stopped == "done" ? 0 : 2;
}

}  // namespace

void addDrive(CLI::App& app) {
  auto args = std::make_shared<DriveArgs>();
  auto* cmd = app.add_subcommand(
      "drive",
      "Headless console: walk a rover or ambler-sim over DDS, auto-approving steps that pass "
      "every interlock, logging everything");
  cmd->add_option("--domain", args->domain, "DDS domain")
      ->check(CLI::Range(0, 232))
      ->capture_default_str();
  cmd->add_option("--rover-id", args->rover_id, "rover to command")->capture_default_str();
  cmd->add_option("--key", args->key, "operator key file {\"operator\", \"key_hex\"}")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--log", args->log, "mission log to create or append to (SQLite)")->required();
  cmd->add_option("--steps", args->steps, "steps to walk")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  cmd->add_flag("--auto-approve", args->auto_approve,
                "release every step that passes its interlocks without asking (required: there "
                "is no operator here)");
  cmd->add_flag("--resume", args->resume,
                "end a hold the rover is in (after a Hold or a link loss) before walking");
  cmd->add_option("--timeout", args->timeout_s, "give up after this long [s]")
      ->check(CLI::Range(1.0, 1e6))
      ->capture_default_str();
  cmd->callback([args] {
    if (const int code = drive(*args); code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace ambler::cli
