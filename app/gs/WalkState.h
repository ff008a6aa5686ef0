#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "executive/ApprovalGate.h"
#include "executive/ReportedStance.h"
#include "executive/TaskTree.h"
#include "executive/WalkExecutive.h"
#include "replay/CommandTable.h"
#include "terrain/ElevationMap.h"

namespace ambler::gs {

// A walk as the views show it at one moment: made on the session's thread
// each time the executive changed, handed to the GUI thread whole, never
// changed after. The map and the table are shared with the state before
// while they are unchanged, so that a view redraws them only when they
// are new.
struct WalkState {
  executive::Phase phase = executive::Phase::kIdle;
  int steps_done = 0;
  std::string suspended_because;         // WalkExecutive::suspendedBecause
  std::string rover_holding;             // empty unless the rover holds
  std::optional<std::string> link_lost;  // why, while the link is lost
  std::optional<executive::StepProposal> pending;
  std::uint64_t proposal_revision = 0;   // changes with each new or edited proposal
  std::optional<gait::Stance> reported;  // the stance the executive plans from
  executive::RoverReport report;         // the rover's newest leg and body states
  std::vector<executive::Task> tasks;
  std::shared_ptr<const terrain::ElevationMap> map;  // the traverse map
  std::shared_ptr<const std::vector<replay::LogRow>> rows =
      std::make_shared<const std::vector<replay::LogRow>>();
  std::optional<double> last_heard_s;  // ground clock; none before the rover spoke
  // The link as the operator must judge it over a delay: the command round
  // trip (smoothed), commands sent and not yet answered, who holds command
  // authority ("alice@..."; this console is `console`) and who asks for it.
  std::optional<double> round_trip_s;
  std::size_t commands_in_flight = 0;
  // The move the rover has taken on and not yet reported the outcome of.
  std::optional<executive::MoveUnderWay> move_under_way;
  std::string authority, authority_request, console;
};

}  // namespace ambler::gs
