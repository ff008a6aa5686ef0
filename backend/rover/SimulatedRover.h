#pragma once

// The rover's side of a link, played by the simulator: it verifies each
// command (signature, sequence, kinematic limits), executes it on the
// simulated Ambler and answers with an acknowledgement and the state that
// changed. Behind the in-process link and behind ambler-sim's DDS endpoint.

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gait/DeadReckoning.h"
#include "link/CommandAuthority.h"
#include "link/Messages.h"
#include "link/Signing.h"
#include "sim/RoverWorld.h"

namespace ambler::rover {

// What the simulated Ambler is and how its execution errs: the rover and
// gait sections of rover.json (its limits), the simulation section (noise,
// slip) and the walking scanner. Ground-station settings are read apart
// (gait::readGaitContext).
struct SimulatedRoverConfig {
  gait::RoverModel model;
  gait::GaitOptions gait;
  sim::ExecutionNoise noise;
  sim::ScannerModel scanner;
};

// Errors name the file and key.
SimulatedRoverConfig readSimulatedRoverConfig(const std::filesystem::path& rover_json,
                                              const std::filesystem::path& scanner_json);
// config/rover.json and config/rover-scanner.json from the resources.
SimulatedRoverConfig readInstalledSimulatedRoverConfig();

struct SimulatedRoverOptions {
  std::uint32_t rover_id = 1;
  sim::CourseOptions course;  // its seed also draws the execution noise
  // A real terrain model, or another procedural terrain (a terrain
  // family's), in place of the course; the course's seed still draws the
  // noise.
  std::optional<sim::DtmSource> dtm;
  std::optional<sim::TerrainDescription> terrain;
  std::vector<link::OperatorKey> operators;
  Box2 scanned_area{-10.0, -8.0, 10.0, 45.0};
  // Hold on its own when no signed command (a GroundHeartbeat at least)
  // has come from the console holding command authority for this long
  // after the first, plus two of the commands' measured one-way delays (a
  // command lost on a long-delay link is resent a round trip later); 0:
  // never.
  double link_timeout_s = 3.0;
  // When the rover's link started (UTC): commands signed before it are
  // refused. Default: when the SimulatedRover is made.
  std::optional<double> started_s;
  // Wall seconds per simulated second. A move or a scan is acknowledged
  // when taken on and its outcome (states, image) comes its modelled
  // duration times this later (finished()); 0: all at once.
  double time_scale = 0.0;
};

class SimulatedRover {
 public:
  // Commands signed before this moment are refused (CommandVerifier::startedAt).
  SimulatedRover(const SimulatedRoverConfig& config, SimulatedRoverOptions options);

  // The acknowledgement first (a NACK with the reason, and nothing else, if
  // refused), then what changed: leg and body states after a move, the range
  // image after AcquireScan; with a time scale, what changed comes from
  // finished() once the move or scan has taken its time, and until then
  // other moves and scans are refused (Hold, Resume and heartbeats are not).
  std::vector<link::Telemetry> handle(const link::Command& command, double now_s);
  // The outcome of the move or scan under way once its time is up (time
  // scale above 0), stamped now; else nothing.
  std::vector<link::Telemetry> finished(double now_s);
  // When that outcome is due (UTC); infinity when nothing is under way.
  double outcomeDueS() const { return outcome_.empty() ? INFINITY : outcome_due_s_; }
  // The NACK for a command refused before it could be read.
  std::vector<link::Telemetry> refuse(const link::Command& command, const std::string& reason,
                                      double now_s) const;
  link::Telemetry heartbeat(double now_s);
  // The link-loss watchdog: the heartbeat that announces the hold (or,
  // already holding, the loss of command authority), the moment the ground
  // has been silent for longer than the timeout.
  std::vector<link::Telemetry> watchLink(double now_s);
  bool holding() const { return !holding_.empty(); }
  const link::CommandAuthority& authority() const { return authority_; }
  // The last change of command authority ("bob@... took command
  // authority"), for the rover's own log; empty when none since asked.
  std::string takeAuthorityChange() { return std::exchange(authority_change_, {}); }
  // Every leg and the body, as the rover reports them now: the encoders'
  // readings and its own dead-reckoned body pose.
  std::vector<link::Telemetry> state(double now_s);
  // Where the rover believes it is; the truth is world().rover().truth(),
  // for evaluations only.
  const gait::Stance& estimate() const { return odometry_.estimate(); }

  std::uint32_t roverId() const { return options_.rover_id; }
  const sim::RoverWorld& world() const { return world_; }
  // For evaluations: the simulator's account of the last move carried out,
  // and the simulated seconds spent moving and scanning so far.
  const sim::MoveReport& lastMove() const { return last_move_; }
  double modelledBusyS() const { return busy_s_; }

 private:
  link::Telemetry message(double now_s, link::TelemetryBody body) const;
  std::vector<link::Telemetry> report(double now_s,
                                      const std::array<sim::LegState, gait::kLegCount>& legs) const;
  std::string carryOut(const link::Command& command, double now_s,
                       std::vector<link::Telemetry>& out);

  SimulatedRoverConfig config_;
  SimulatedRoverOptions options_;
  sim::RoverWorld world_;
  gait::KinematicOdometry odometry_;
  link::CommandVerifier verifier_;
  link::CommandAuthority authority_;
  std::string authority_change_;
  std::uint64_t heartbeats_ = 0, scans_ = 0;
  std::string holding_;                 // why the rover holds; empty: it does not
  std::optional<double> last_heard_s_;  // the last command from the console in command
  double delay_s_ = 0.0;                // its one-way delay, smoothed, rising at once
  sim::MoveReport last_move_;
  double busy_s_ = 0.0;
  // The outcome of the move or scan under way (time scale above 0), what
  // it was, and when it is due (UTC).
  std::vector<link::Telemetry> outcome_;
  std::string under_way_;
  double outcome_due_s_ = 0.0;
};

}  // namespace ambler::rover
