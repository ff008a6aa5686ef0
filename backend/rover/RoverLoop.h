#pragma once

// The rover's loop, whatever carries its messages: the full state once,
// then each command as it comes (a NACK for one that arrived malformed),
// a heartbeat whenever a period passes, and a hold when the ground falls
// silent for longer than the rover's link timeout.

#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include "rover/SimulatedRover.h"

namespace ambler::rover {

struct Incoming {
  link::Command command;  // at least rover id, operator and sequence when malformed
  std::string malformed;  // why it could not be read; empty when it could
};

struct RoverLoopIo {
  // Commands that arrived, waiting up to the timeout while none has; an
  // empty list when stopping.
  std::function<std::vector<Incoming>(std::chrono::milliseconds)> receive;
  std::function<void(const link::Telemetry&)> publish;
  std::function<bool()> stopping;
  // Optional: called after each command is handled, before its answer goes.
  std::function<void(const link::Command&, const SimulatedRover&)> handled;
  // Optional: the rover's own log, a line per refused command (with the
  // reason) and per change of command authority.
  std::function<void(const std::string&)> note;
};

void runRoverLoop(SimulatedRover& rover, std::chrono::milliseconds heartbeat_period,
                  const RoverLoopIo& io);

}  // namespace ambler::rover
