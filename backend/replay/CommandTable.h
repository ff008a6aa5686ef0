#pragma once

#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "link/Messages.h"
#include "missionlog/MissionLog.h"

namespace ambler::replay {

// One line of the event and command table: a command and what the rover
// answered, an operator's decision, a change in the rover's hold, or an
// event of the ground's walk (a stop and why, the link lost and back).
struct LogRow {
  double time_s = 0.0;
  std::string who;      // operator id, "rover", or "ground" for the walk's events
  std::string what;     // "LegMove leg 2, 3 waypoints", "approved proposal 4", ...
  std::string outcome;  // "accepted", "refused", "no answer", a verdict, ...
  std::string reason;   // why refused, what was decided
  bool operator==(const LogRow&) const = default;
};

// The table as messages pass (live) or as a log is read (replay): each
// command is answered in place by the acknowledgement with its operator,
// console and sequence; changes of hold and command authority get rows. Heartbeats the rover
// accepted are left out as noise.
class CommandTable {
 public:
  void sent(double time_s, const link::Command& command);
  void received(double time_s, const link::Telemetry& message);
  void decided(const missionlog::Decision& decision);
  // An event of the walk (WalkExecutive's), in its own words.
  void noted(double time_s, const std::string& what);

  const std::vector<LogRow>& rows() const { return rows_; }
  // Commands sent and not answered yet (heartbeats left out).
  std::size_t awaiting() const { return open_.size(); }
  // From the rover's newest heartbeat: the console holding command
  // authority and one asking for it; empty: none.
  const std::string& authority() const { return authority_; }
  const std::string& authorityRequest() const { return authority_request_; }
  std::vector<LogRow> takeRows() { return std::move(rows_); }

 private:
  void answer(double time_s, const link::CommandAck& ack);

  using Key = std::tuple<std::string, std::uint64_t, std::uint64_t>;  // operator, console, sequence
  std::vector<LogRow> rows_;
  std::map<Key, std::size_t> open_;  // commands awaiting their answer
  std::map<Key, std::pair<double, std::string>> heartbeats_;
  bool holding_ = false;
  std::string authority_, authority_request_;
};

// "LegMove leg 2, 3 waypoints", "BodyMove (0.000, 0.450) m, 0.000 deg", ...
std::string describeCommand(const link::CommandBody& body);

// What a decision was about, as a sentence with units: "leg 2 to (1.20,
// 3.40, -0.05) m, body moves 0.52 m, turns 15.0 deg, least stability
// margin 0.15 m, interlocks passed; reason: ..."; a detail that is not the
// gate's JSON is shown as it is.
std::string describeDecision(const std::string& detail);

}  // namespace ambler::replay
