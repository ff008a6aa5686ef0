#include "rover/RoverLoop.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace ambler::rover {

namespace {

void noteOutcome(const link::Command& command, const std::vector<link::Telemetry>& out,
                 SimulatedRover& rover, const std::function<void(const std::string&)>& note) {
  for (const auto& t : out)
    if (const auto* ack = std::get_if<link::CommandAck>(&t.body); ack && !ack->accepted)
      note("refused " + link::typeName(command.body) + " " + std::to_string(command.sequence) +
           " from " + link::consoleName(command.operator_id, command.console_id) + ": " +
           ack->reason);
  if (const auto change = rover.takeAuthorityChange(); !change.empty()) note(change);
}

}  // namespace

void runRoverLoop(SimulatedRover& rover, std::chrono::milliseconds heartbeat_period,
                  const RoverLoopIo& io) {
  using Clock = std::chrono::steady_clock;
  // Commands are stamped and judged in UTC, and so is the telemetry.
  const auto now_s = link::utcNowS;
  for (const auto& t : rover.state(now_s())) io.publish(t);
  auto next_heartbeat = Clock::now();
  while (!io.stopping()) {
    // Short waits, so that the link watchdog holds soon after its timeout,
    // and none past the moment a move's outcome is due.
    using std::chrono::milliseconds;
    const auto to_heartbeat = std::chrono::ceil<milliseconds>(next_heartbeat - Clock::now());
    const auto to_outcome =
        milliseconds(std::int64_t(std::ceil(1e3 * std::min(rover.outcomeDueS() - now_s(), 1.0))));
    const auto wait =
        std::clamp(std::min(to_heartbeat, to_outcome), milliseconds(0), milliseconds(50));
    for (const auto& in : io.receive(wait)) {
      const auto out = in.malformed.empty() ? rover.handle(in.command, now_s())
                                            : rover.refuse(in.command, in.malformed, now_s());
      if (io.handled) io.handled(in.command, rover);
      if (io.note) noteOutcome(in.command, out, rover, io.note);
      for (const auto& t : out) io.publish(t);
    }
    for (const auto& t : rover.finished(now_s())) io.publish(t);
    for (const auto& t : rover.watchLink(now_s())) {
      if (const auto* h = std::get_if<link::Heartbeat>(&t.body); h && io.note)
        io.note("holds: " + h->hold_reason);
      io.publish(t);
    }
    if (const auto lost = rover.takeAuthorityChange(); io.note && !lost.empty()) io.note(lost);
    if (Clock::now() >= next_heartbeat) {
      io.publish(rover.heartbeat(now_s()));
      next_heartbeat += heartbeat_period;
    }
  }
}

}  // namespace ambler::rover
