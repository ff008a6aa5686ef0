#include "rover/RoverLoop.h"

#include <algorithm>

namespace ambler::rover {

void runRoverLoop(SimulatedRover& rover, std::chrono::milliseconds heartbeat_period,
                  const RoverLoopIo& io) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto now_s = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  for (const auto& t : rover.state(now_s())) io.publish(t);
  auto next_heartbeat = Clock::now();
  while (!io.stopping()) {
    // Short waits, so that the link watchdog holds soon after its timeout.
    const auto wait = std::clamp(
        std::chrono::duration_cast<std::chrono::milliseconds>(next_heartbeat - Clock::now()),
        std::chrono::milliseconds(0), std::chrono::milliseconds(50));
    for (const auto& in : io.receive(wait)) {
      const auto out = in.malformed.empty() ? rover.handle(in.command, now_s())
                                            : rover.refuse(in.command, in.malformed, now_s());
      if (io.handled) io.handled(in.command, rover);
      for (const auto& t : out) io.publish(t);
    }
    for (const auto& t : rover.watchLink(now_s())) io.publish(t);
    if (Clock::now() >= next_heartbeat) {
      io.publish(rover.heartbeat(now_s()));
      next_heartbeat += heartbeat_period;
    }
  }
}

}  // namespace ambler::rover
