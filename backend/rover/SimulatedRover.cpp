#include "rover/SimulatedRover.h"

#include <algorithm>
#include <sstream>

#include "core/Resources.h"
#include "gait/RoverConfig.h"
#include "link/Limits.h"

namespace ambler::rover {

namespace {

// The Perceptron delivers 2 frames a second (cmu-1990).
constexpr double kScanFrameS = 0.5;

sim::RoverWorld makeWorld(const SimulatedRoverConfig& config, const SimulatedRoverOptions& o) {
  if (o.dtm)
    return sim::RoverWorld(std::make_unique<sim::HeightfieldTerrain>(sim::loadDtm(*o.dtm)),
                           o.course.seed, config.model, config.gait, config.noise, config.scanner,
                           o.scanned_area);
  if (o.terrain)
    return sim::RoverWorld(std::make_unique<sim::ProceduralTerrain>(*o.terrain), o.course.seed,
                           config.model, config.gait, config.noise, config.scanner, o.scanned_area);
  return sim::RoverWorld(o.course, config.model, config.gait, config.noise, config.scanner,
                         o.scanned_area);
}

}  // namespace

SimulatedRoverConfig readSimulatedRoverConfig(const std::filesystem::path& rover_json,
                                              const std::filesystem::path& scanner_json) {
  const gait::GaitContext limits = gait::readRoverConfig(rover_json);
  return {limits.model, limits.gait, sim::readExecutionNoise(rover_json),
          sim::readScannerModel(scanner_json)};
}

SimulatedRoverConfig readInstalledSimulatedRoverConfig() {
  return readSimulatedRoverConfig(findResource("config/rover.json"),
                                  findResource("config/rover-scanner.json"));
}

SimulatedRover::SimulatedRover(const SimulatedRoverConfig& config, SimulatedRoverOptions options)
    : config_(config),
      options_(std::move(options)),
      world_(makeWorld(config, options_)),
      odometry_(config.model, world_.rover().truth()),
      verifier_(options_.rover_id, options_.operators) {
  verifier_.startedAt(options_.started_s.value_or(link::utcNowS()));
}

link::Telemetry SimulatedRover::message(double now_s, link::TelemetryBody body) const {
  return {options_.rover_id, now_s, std::move(body)};
}

link::Telemetry SimulatedRover::heartbeat(double now_s) {
  return message(now_s, link::Heartbeat{++heartbeats_, holding(), holding_, authority_.holder(),
                                        authority_.request()});
}

std::vector<link::Telemetry> SimulatedRover::watchLink(double now_s) {
  if (options_.link_timeout_s <= 0 || !last_heard_s_) return {};
  // Held already, the rover has nothing to stop; but a holder that falls
  // silent still loses command authority, or a console that died holding
  // it (after taking it back with a command late from an outage) would
  // keep every other console from resuming.
  if (holding() && !authority_.held()) return {};
  const double silent_s = now_s - *last_heard_s_;
  if (silent_s <= options_.link_timeout_s + 2.0 * delay_s_) return {};
  if (!holding()) {
    std::ostringstream why;
    why.precision(1);
    why << std::fixed << "link lost: no command or heartbeat from the ground for " << silent_s
        << " s";
    holding_ = why.str();
  }
  const std::string lost = authority_.held() ? authority_.holder() + " lost command authority" : "";
  const std::string next = authority_.lapse();
  // A console that had asked now holds authority: its silence counts from now.
  if (authority_.held()) last_heard_s_ = now_s;
  authority_change_ = lost + (!lost.empty() && !next.empty() ? "; " : "") + next;
  return {heartbeat(now_s)};
}

std::vector<link::Telemetry> SimulatedRover::state(double now_s) {
  return report(now_s, world_.rover().legStates());
}

// A real rover knows its body only from its encoders, and so does this one:
// it reports the pose it dead-reckons, which drifts from the truth.
std::vector<link::Telemetry> SimulatedRover::report(
    double now_s, const std::array<sim::LegState, gait::kLegCount>& legs) const {
  std::vector<link::Telemetry> out;
  for (int leg = 0; leg < gait::kLegCount; ++leg) {
    const auto& s = legs[std::size_t(leg)];
    out.push_back(message(now_s, link::LegState{leg, s.joints, s.contact, s.force_n}));
  }
  const auto& body = odometry_.estimate().body;
  out.push_back(message(
      now_s, link::BodyState{body.xy.x(), body.xy.y(), body.link_z, body.heading_rad, false}));
  return out;
}

std::vector<link::Telemetry> SimulatedRover::refuse(const link::Command& command,
                                                    const std::string& reason, double now_s) const {
  return {message(now_s, link::CommandAck{command.operator_id, command.console_id, command.sequence,
                                          false, reason})};
}

std::vector<link::Telemetry> SimulatedRover::handle(const link::Command& command, double now_s) {
  if (const auto unverified = verifier_.check(command, now_s); unverified.refused())
    return refuse(command, unverified.why(), now_s);
  std::string change;
  if (const auto not_in_command = authority_.admit(command, change); not_in_command.refused())
    return refuse(command, not_in_command.why(), now_s);
  // A watching console's heartbeats must not keep the rover going for a
  // commanding console that died.
  if (!authority_.held() ||
      authority_.holder() == link::consoleName(command.operator_id, command.console_id)) {
    last_heard_s_ = now_s;
    const double delay = std::max(0.0, now_s - command.time_s);
    delay_s_ = delay > delay_s_ ? delay : 0.95 * delay_s_ + 0.05 * delay;
  }
  // The next heartbeat announces it.
  if (!change.empty()) authority_change_ = change;
  if (std::holds_alternative<link::GroundHeartbeat>(command.body)) return {};
  std::string reason;
  const bool moves = std::holds_alternative<link::LegMove>(command.body) ||
                     std::holds_alternative<link::BodyMove>(command.body) ||
                     std::holds_alternative<link::Grasp>(command.body);
  if (moves && holding()) reason = "holding (" + holding_ + "): send Resume first";
  if (reason.empty() && (moves || std::holds_alternative<link::AcquireScan>(command.body)) &&
      !outcome_.empty())
    reason = "busy: " + under_way_ + " under way";
  if (reason.empty()) reason = link::outsideLimits(command.body, config_.model, config_.gait).why();
  std::vector<link::Telemetry> changes;
  const double busy_before = busy_s_;
  const gait::BodyPose before = odometry_.estimate().body;
  if (reason.empty()) reason = carryOut(command, now_s, changes);
  std::vector<link::Telemetry> out{
      message(now_s, link::CommandAck{command.operator_id, command.console_id, command.sequence,
                                      reason.empty(), reason})};
  if (reason.empty() && options_.time_scale > 0 && busy_s_ > busy_before) {
    outcome_ = std::move(changes);
    under_way_ = link::typeName(command.body) + " " + std::to_string(command.sequence);
    outcome_due_s_ = now_s + (busy_s_ - busy_before) * options_.time_scale;
    // Said at once, and kept on the state topic for a console that joins
    // before the outcome: until then the rover takes no scan.
    if (moves)
      out.push_back(message(now_s, link::BodyState{before.xy.x(), before.xy.y(), before.link_z,
                                                   before.heading_rad, true}));
    return out;
  }
  out.insert(out.end(), changes.begin(), changes.end());
  return out;
}

std::vector<link::Telemetry> SimulatedRover::finished(double now_s) {
  if (outcome_.empty() || now_s < outcome_due_s_) return {};
  for (auto& t : outcome_) t.time_s = now_s;
  return std::exchange(outcome_, {});
}

std::string SimulatedRover::carryOut(const link::Command& command, double now_s,
                                     std::vector<link::Telemetry>& out) {
  const auto& body = command.body;
  if (const auto* m = std::get_if<link::AcquireScan>(&body)) {
    busy_s_ += kScanFrameS;
    if (m->sensor == link::ScanSensor::kLightStriper) {
      if (!world_.hasStriper()) return "no light striper on a terrain model";
      out.push_back(message(now_s, world_.striperScan(++scans_)));
    } else {
      sensor::RangeImage image = world_.scan(++scans_);
      image.sensor_to_world = world_.mountPose(odometry_.estimate().body);  // where it believes
      out.push_back(message(now_s, std::move(image)));
    }
    return {};
  }
  if (std::holds_alternative<link::Grasp>(body)) return "this rover has no manipulator";
  if (std::holds_alternative<link::RequestAuthority>(body) ||
      std::holds_alternative<link::HandOver>(body))
    return {};
  if (std::holds_alternative<link::Hold>(body)) {
    // Every move completes (a move under way carries on to its end), so
    // holding is refusing the next motion. A hold already in force keeps its reason:
    // the first is what the operator needs to know.
    if (!holding()) holding_ = "Hold from " + command.operator_id;
    out.push_back(heartbeat(now_s));
    return {};
  }
  if (std::holds_alternative<link::Resume>(body)) {
    holding_.clear();
    out.push_back(heartbeat(now_s));  // and the whole state, for a console that joins now,
    // but not before the outcome of a move under way: it would report the
    // move's end before its time.
    if (!outcome_.empty()) return {};
  } else if (const auto* m = std::get_if<link::LegMove>(&body)) {
    last_move_ = world_.rover().executeLeg({m->leg, m->waypoints});
    busy_s_ += last_move_.duration_s;
  } else if (const auto* m = std::get_if<link::BodyMove>(&body)) {
    last_move_ = world_.rover().executeBody({{m->x_m, m->y_m}, m->rotation_rad, m->raise_m});
    busy_s_ += last_move_.duration_s;
  }
  // The readings reported are the ones the rover dead-reckons from.
  const auto legs = world_.rover().legStates();
  if (const auto* m = std::get_if<link::LegMove>(&body))
    odometry_.legMoved(m->leg, legs[std::size_t(m->leg)].joints);
  else if (std::holds_alternative<link::BodyMove>(body))
    odometry_.bodyMoved(sim::jointsOf(legs));
  const auto states = report(now_s, legs);
  out.insert(out.end(), states.begin(), states.end());
  return {};
}

}  // namespace ambler::rover
