// ambler-cli drive: a headless console. It walks a rover (or ambler-sim)
// over DDS with the executive in auto-approve mode, so every interlock
// still runs, and records everything in a mission log. It prints one JSON
// line per event, per acknowledgement and per change of command
// authority, each after the log has it, then a summary. --watch only
// watches and records; --take-over watches until SIGUSR1, then asks for
// command authority and walks once it has it; --hand-over gives authority,
// between two steps, to a console that asks.
#include <array>
#include <atomic>
#include <csignal>
#include <iostream>
#include <iterator>
#include <memory>
#include <optional>
#include <set>
#include <vector>

#include "cli/Arguments.h"
#include "cli/Commands.h"
#include "executive/WalkExecutive.h"
#include "gait/RoverConfig.h"
#include "link/Signing.h"
#include "link/dds/DdsMessages.h"
#include "missionlog/ReplayLinks.h"

namespace ambler::cli {

namespace {

std::atomic<bool> g_take_over{false}, g_stop{false};

struct DriveArgs {
  std::uint32_t domain = 0;
  std::uint32_t rover_id = 1;
  std::string key;
  std::string log;
  int steps = 5;
  WalkPath path;
  bool auto_approve = false, resume = false, watch = false, take_over = false, hand_over = false;
  double timeout_s = 600.0;
  double validity_s = 10.0;
  double discovery_wait_s = 30.0;
};

void printLine(const nlohmann::json& line) { std::cout << line.dump() << std::endl; }

// The console's view of the link: prints each acknowledgement (this
// console's, with the command it answers, and other consoles') and each
// change of command authority as they come out of the recording link, and
// measures approval-to-motion latency: from an approval to the rover's
// acknowledgement (rover clock, UTC) of the step's first move.
class ConsoleLink : public link::Link {
 public:
  ConsoleLink(link::Link& inner, std::string console) : inner_(inner), me_(std::move(console)) {}

  void send(const link::Command& command) override {
    const bool moves = std::holds_alternative<link::LegMove>(command.body) ||
                       std::holds_alternative<link::BodyMove>(command.body);
    if (moves && approved_s_) first_move_ = {command.sequence, *std::exchange(approved_s_, {})};
    inner_.send(command);
    if (std::holds_alternative<link::GroundHeartbeat>(command.body)) return;
    unanswered_[command.sequence] = link::typeName(command.body);
    ++sent_;
  }

  std::vector<link::Telemetry> receive(std::chrono::milliseconds timeout) override {
    auto in = inner_.receive(timeout);
    for (const auto& t : in) {
      if (const auto* a = std::get_if<link::CommandAck>(&t.body)) onAck(*a, t.time_s);
      if (const auto* h = std::get_if<link::Heartbeat>(&t.body))
        onHeartbeat(*h), last_heartbeat_s_ = t.time_s;
      if (const auto* leg = std::get_if<link::LegState>(&t.body);
          leg && leg->leg >= 0 && leg->leg < gait::kLegCount)
        state_[std::size_t(leg->leg)] = t;
      if (std::holds_alternative<link::BodyState>(t.body)) state_.back() = t;
    }
    in.insert(in.begin(), std::make_move_iterator(replay_.begin()),
              std::make_move_iterator(replay_.end()));
    replay_.clear();
    return in;
  }
  // The next receive() hands on again the newest leg and body states this
  // link has seen: a walk that starts after the console read them (waiting
  // for command authority) learns from them where the rover stands, and
  // whether a move is under way, which a rover mid-move would not report
  // again before the move's end.
  void replayState() {
    for (const auto& t : state_)
      if (t) replay_.push_back(*t);
  }
  std::string describe() const override { return inner_.describe(); }

  void approved(double now_s) { approved_s_ = now_s; }
  std::size_t unanswered() const { return unanswered_.size(); }
  // Each command not yet answered, as "type sequence".
  std::vector<std::string> unansweredCommands() const {
    std::vector<std::string> out;
    for (const auto& [sequence, type] : unanswered_)
      out.push_back(type + " " + std::to_string(sequence));
    return out;
  }
  // The rover time of its newest heartbeat.
  double lastHeartbeatS() const { return last_heartbeat_s_; }
  bool heardHeartbeat() const { return last_heartbeat_s_ > kNever; }
  const std::string& holder() const { return holder_; }
  const std::string& request() const { return request_; }

  nlohmann::json figures() const {
    return {{"commands_sent", sent_},  // heartbeats left out
            {"acks", acks_},
            {"refused", refused_},
            {"unanswered", unanswered_.size()},
            {"unanswered_commands", unansweredCommands()},
            {"other_consoles_acks", others_acks_},
            {"approval_to_motion_s", distribution(latencies_s_)}};
  }

 private:
  void onAck(const link::CommandAck& a, double rover_time_s) {
    const std::string console = link::consoleName(a.operator_id, a.console_id);
    if (console != me_) {
      ++others_acks_;
      printLine({{"ack", a.sequence},
                 {"console", console},
                 {"accepted", a.accepted},
                 {"reason", a.reason}});
      return;
    }
    const auto it = unanswered_.find(a.sequence);
    const std::string what = it != unanswered_.end() ? it->second : "GroundHeartbeat";
    if (it != unanswered_.end()) unanswered_.erase(it);
    ++acks_;
    refused_ += !a.accepted;
    if (first_move_ && first_move_->first == a.sequence && a.accepted)
      latencies_s_.push_back(rover_time_s - first_move_->second);
    printLine(
        {{"ack", a.sequence}, {"command", what}, {"accepted", a.accepted}, {"reason", a.reason}});
  }

  void onHeartbeat(const link::Heartbeat& h) {
    if (h.authority == holder_ && h.authority_request == request_) return;
    holder_ = h.authority, request_ = h.authority_request;
    printLine({{"authority", holder_}, {"request", request_}, {"me", me_}});
  }

  link::Link& inner_;
  std::array<std::optional<link::Telemetry>, gait::kLegCount + 1> state_;  // legs, then the body
  std::vector<link::Telemetry> replay_;
  std::string me_, holder_, request_;
  std::optional<double> approved_s_;
  std::optional<std::pair<std::uint64_t, double>> first_move_;  // sequence, approved at
  std::map<std::uint64_t, std::string> unanswered_;
  std::vector<double> latencies_s_;
  long sent_ = 0, acks_ = 0, refused_ = 0, others_acks_ = 0;
  static constexpr double kNever = -1e300;
  double last_heartbeat_s_ = kNever;
};

// Everything a console has: its mission log, the DDS link recorded into
// it, the link's health and the printing view.
struct Console {
  Console(const DriveArgs& a, const std::string& me)
      : log(a.log, "drive rover " + std::to_string(a.rover_id)),
        dds(a.domain, a.rover_id,
            std::chrono::milliseconds(static_cast<long>(a.discovery_wait_s * 1000))),
        recording(dds, log),
        watched(recording, health, link::utcNowS),
        link(watched, me) {}
  missionlog::MissionLog log;
  link::dds::DdsLink dds;
  missionlog::RecordingLink recording;
  link::LinkHealth health;
  link::WatchedLink watched;
  ConsoleLink link;
};

// Prints the link's state at first, then each time it turns stale or
// fresh (nothing heard for 3 s).
void reportStaleness(Console& c, double now_s, double start_s, std::optional<bool>& stale) {
  if (stale == c.health.stale(now_s)) return;
  stale = c.health.stale(now_s);
  const auto age = c.health.ageS(now_s);
  printLine({{"link", *stale ? "stale" : "fresh"},
             {"age_s", age ? nlohmann::json(*age) : nlohmann::json()},
             {"t_s", now_s - start_s}});
}

void sendSigned(Console& c, link::CommandSigner& signer, std::uint32_t rover_id,
                link::CommandBody body) {
  c.link.send(signer.command(rover_id, std::move(body)));
}

// Watches and records until SIGTERM, the timeout, or (taking over) SIGUSR1.
void watch(Console& c, const DriveArgs& a, double start_s, bool until_take_over) {
  std::optional<bool> stale;
  while (!g_stop && !(until_take_over && g_take_over) && link::utcNowS() - start_s < a.timeout_s) {
    c.link.receive(std::chrono::milliseconds(50));
    reportStaleness(c, link::utcNowS(), start_s, stale);
  }
}

// Asks for command authority and waits until the rover says this console
// holds it; false on the timeout.
bool takeOver(Console& c, link::CommandSigner& signer, const DriveArgs& a, double start_s) {
  sendSigned(c, signer, a.rover_id, link::RequestAuthority{});
  printLine({{"event", "asked for command authority"}, {"t_s", link::utcNowS() - start_s}});
  while (c.link.holder() != signer.console()) {
    if (link::utcNowS() - start_s > a.timeout_s) return false;
    c.link.receive(std::chrono::milliseconds(50));
  }
  return true;
}

// A console resuming may find command authority with another console: the
// one it replaces, which took it back with a command late from the outage
// and then stopped (its silence hands authority on to a console that asked),
// or one still in command (which has to hand over). It asks and waits, as a
// take-over does, even when the last heartbeat named no holder: that
// heartbeat may predate such a late command, and the rover refuses a Resume
// sent on its word. Asking when nobody holds authority is granted at once.
// False on the timeout.
bool authorityToResume(Console& c, link::CommandSigner& signer, const DriveArgs& a,
                       double start_s) {
  const double until_s = link::utcNowS() + a.discovery_wait_s;
  while (!c.link.heardHeartbeat() && link::utcNowS() < until_s)
    c.link.receive(std::chrono::milliseconds(50));
  const std::string holder = c.link.holder();
  if (holder == signer.console()) return true;
  if (!holder.empty())
    printLine({{"event", holder + " holds command authority"}, {"t_s", link::utcNowS() - start_s}});
  return takeOver(c, signer, a, start_s);
}

// Why the walk stops, or empty while it goes on.
std::string stopReason(const executive::WalkExecutive& executive,
                       const executive::ApprovalGate& gate, double elapsed_s, double timeout_s) {
  const auto& pending = gate.pending();
  if (executive.phase() == executive::Phase::kDone) return "done";
  if (executive.phase() == executive::Phase::kSuspended) return "suspended";
  if (pending && !pending->interlocks.passed())
    return "step fails interlock " + pending->interlocks.firstFailure() +
           "; no operator here to edit or reject it";
  if (elapsed_s > timeout_s) return "timed out";
  return {};
}

// Another console asks for authority: no new step is released; between two
// steps (a proposal waiting, nothing in flight) authority goes to it. The
// hand-over's acknowledgement and the heartbeat naming the new holder come
// on different topics: both are waited for, so that the log has both.
bool handOverBetweenSteps(Console& c, link::CommandSigner& signer, executive::ApprovalGate& gate,
                          executive::WalkExecutive& executive, const DriveArgs& a) {
  if (c.link.request().empty() || c.link.holder() != signer.console()) return false;
  gate.setMode(executive::ApprovalMode::kOperator);
  if (executive.phase() != executive::Phase::kAwaitingDecision) return false;
  sendSigned(c, signer, a.rover_id, link::HandOver{c.link.request()});
  const double asked_s = link::utcNowS();
  while ((c.link.unanswered() > 0 || c.link.holder() == signer.console()) &&
         link::utcNowS() - asked_s < executive.ackTimeoutS())
    executive.poll(link::utcNowS(), std::chrono::milliseconds(50));
  if (c.link.holder() != signer.console()) return true;
  // Refused (the request went away): walk on, the waiting step released.
  gate.setMode(executive::ApprovalMode::kAutoApprove);
  if (const auto& pending = gate.pending(); pending && pending->interlocks.passed())
    (void)gate.approve(pending->id, executive::kAutoApprover, link::utcNowS());
  return false;
}

// What a console that stopped still waits for, so that a long wait says why.
std::string awaited(const ConsoleLink& link) {
  const auto commands = link.unansweredCommands();
  if (commands.empty()) return "a heartbeat the rover sent after the stop";
  std::string list;
  for (const auto& c : commands) list += (list.empty() ? "" : ", ") + c;
  return "the answer" + std::string(commands.size() > 1 ? "s" : "") + " to " + list;
}

int walk(Console& c, link::CommandSigner& signer, const DriveArgs& a, double start_s) {
  const auto context = gait::readInstalledGaitContext();
  executive::ApprovalGate gate([&](const missionlog::Decision& d) {
    c.log.record(d);
    if (d.verdict == missionlog::Verdict::kApproved) c.link.approved(d.time_s);
  });
  gate.setMode(executive::ApprovalMode::kAutoApprove);
  executive::ExecutiveOptions options;
  options.rover_id = a.rover_id;
  options.steps = a.steps;
  options.heading = a.path.heading();
  executive::WalkExecutive executive(c.link, signer, gate, context, options);
  executive.onProduct([&](double t, const std::string& kind, const std::string& parameters) {
    c.log.recordProduct(t, kind, parameters);
  });
  executive.onEvent(
      [&](const executive::ExecutiveEvent& e) { c.log.recordEvent(e.time_s, e.what); });

  std::size_t printed = 0;
  auto printEvents = [&](double now_s) {
    for (; printed < executive.events().size(); ++printed)
      printLine({{"event", executive.events()[printed].what}, {"t_s", now_s - start_s}});
  };
  // A console that took over has watched the rover's state go by; a Resume
  // has the rover report it all again (and ends a hold), unless a move is
  // under way: what it saw is handed on, which says so.
  if (a.resume || a.take_over) c.link.replayState();
  executive.start(link::utcNowS(), a.resume || a.take_over);
  std::string stopped;
  std::optional<bool> stale;
  // One turn of the console: poll, then say what changed. The staleness is
  // judged after the poll's wait: what it heard is older than now, never
  // newer.
  const auto turn = [&] {
    const double now_s = link::utcNowS();
    executive.poll(now_s, std::chrono::milliseconds(50));
    reportStaleness(c, link::utcNowS(), start_s, stale);
    printEvents(now_s);
    return now_s;
  };
  while (stopped.empty()) {
    const double now_s = turn();
    stopped = stopReason(executive, gate, now_s - start_s, a.timeout_s);
    if (stopped.empty() && a.hand_over && handOverBetweenSteps(c, signer, gate, executive, a))
      stopped = "handed over to " + c.link.holder();
  }
  // Commands may still be in flight (a link that comes back delivers them
  // late): their answers, and after a suspension the rover's word on
  // holding (a heartbeat sent after it), are waited for, as long as the
  // console's timeout allows, so that the log has them.
  const double stopped_s = link::utcNowS();
  const auto settled = [&] {
    const double now_s = link::utcNowS();
    return c.link.unanswered() == 0 &&
           (stopped != "suspended" ||
            (!c.health.stale(now_s) && c.link.lastHeartbeatS() >= stopped_s));
  };
  if (!settled())
    printLine({{"event", "stopped (" + stopped + "); waiting for " + awaited(c.link)},
               {"t_s", stopped_s - start_s}});
  while (!settled() && link::utcNowS() - start_s < a.timeout_s) turn();
  auto summary = c.link.figures();
  summary.update({{"stopped", stopped},
                  {"steps_done", executive.stepsDone()},
                  {"steps_planned_ahead", executive.stepsPlannedAhead()},
                  {"round_trip_s", executive.roundTripS() ? nlohmann::json(*executive.roundTripS())
                                                          : nlohmann::json()},
                  {"console", signer.console()},
                  {"log", a.log},
                  {"duration_s", link::utcNowS() - start_s}});
  printLine(summary);
  const bool ok = stopped == "done" || stopped.rfind("handed over", 0) == 0;
  return ok ? 0 : 2;
}

int drive(const DriveArgs& a) {
  if (!a.auto_approve && !a.watch)
    throw std::invalid_argument(
        "drive has no operator to ask: pass --auto-approve (every interlock still runs) or "
        "approve steps in ambler-gs");
  if (!a.watch && a.key.empty()) throw std::invalid_argument("--key is needed to command");
  std::signal(SIGUSR1, [](int) { g_take_over = true; });
  std::signal(SIGTERM, [](int) { g_stop = true; });
  std::signal(SIGINT, [](int) { g_stop = true; });
  std::optional<link::CommandSigner> signer;
  if (!a.key.empty())
    signer.emplace(link::readOperatorKey(a.key), missionlog::firstSequenceFromClock(),
                   link::SignerOptions{.validity_s = a.validity_s});
  const std::string me = signer ? signer->console() : "watcher";
  Console c(a, me);
  const double start_s = link::utcNowS();
  printLine({{"event", "waiting for the rover's state on " + c.link.describe()},
             {"console", me},
             {"t_s", 0.0}});
  if (a.watch || a.take_over) watch(c, a, start_s, a.take_over);
  if (a.watch || g_stop) {
    auto summary = c.link.figures();
    summary.update({{"stopped", "watched"}, {"console", me}, {"log", a.log}});
    printLine(summary);
    return 0;
  }
  if ((a.take_over && !takeOver(c, *signer, a, start_s)) ||
      (a.resume && !authorityToResume(c, *signer, a, start_s))) {
    printLine({{"stopped", "no command authority within the timeout"}});
    return 2;
  }
  return walk(c, *signer, a, start_s);
}

}  // namespace

void addDrive(CLI::App& app) {
  auto args = std::make_shared<DriveArgs>();
  auto* cmd = app.add_subcommand(
      "drive",
      "Headless console: walk a rover or ambler-sim over DDS, auto-approving steps that pass "
      "every interlock, logging everything; or watch and log");
  cmd->add_option("--domain", args->domain, "DDS domain")
      ->check(CLI::Range(0, 232))
      ->capture_default_str();
  cmd->add_option("--rover-id", args->rover_id, "rover to command")->capture_default_str();
  cmd->add_option("--key", args->key, "operator key file {\"operator\", \"key_hex\"}")
      ->check(CLI::ExistingFile);
  cmd->add_option("--log", args->log, "mission log to create or append to (SQLite)")->required();
  cmd->add_option("--steps", args->steps, "steps to walk")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  addWalkPathOptions(*cmd, args->path);
  cmd->add_flag("--auto-approve", args->auto_approve,
                "release every step that passes its interlocks without asking (required: there "
                "is no operator here)");
  cmd->add_flag("--resume", args->resume,
                "end a hold the rover is in (after a Hold or a link loss) before walking, after "
                "asking for command authority and waiting for it (another console may hold it)");
  cmd->add_flag("--watch", args->watch,
                "only watch and record (no key needed) until SIGTERM or the timeout");
  cmd->add_flag("--take-over", args->take_over,
                "watch until SIGUSR1, then ask for command authority and walk once it is handed "
                "over");
  cmd->add_flag("--hand-over", args->hand_over,
                "when another console asks for command authority, hand it over between two "
                "steps and stop");
  cmd->add_option("--validity", args->validity_s,
                  "validity window of each command [s]: the rover refuses one arriving later")
      ->check(CLI::Range(0.01, 600.0))
      ->capture_default_str();
  cmd->add_option("--discovery-wait", args->discovery_wait_s,
                  "how long a command waits for the rover to be discovered [s]")
      ->check(CLI::Range(0.1, 600.0))
      ->capture_default_str();
  cmd->add_option("--timeout", args->timeout_s, "give up after this long [s]")
      ->check(CLI::Range(1.0, 1e6))
      ->capture_default_str();
  cmd->callback([args] {
    if (const int code = drive(*args); code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace ambler::cli
