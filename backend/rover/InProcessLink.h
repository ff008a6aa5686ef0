#pragma once

// The built-in simulator as a link (QGroundControl's MockLink): the
// simulated rover runs on its own thread in this process, takes commands
// from a queue and sends telemetry back, with a heartbeat every period.

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>

#include "link/Link.h"
#include "rover/RoverLoop.h"
#include "rover/SimulatedRover.h"

namespace ambler::rover {

// Sees the simulated rover on its thread after each command it handled,
// before the answer goes out: how evaluations score a walk against the
// truth, which the ground never sees.
using RoverObserver = std::function<void(const link::Command&, const SimulatedRover&)>;

class InProcessLink : public link::Link {
 public:
  InProcessLink(const SimulatedRoverConfig& config, SimulatedRoverOptions options,
                std::chrono::milliseconds heartbeat_period = std::chrono::milliseconds(1000),
                RoverObserver observer = {});
  ~InProcessLink() override;

  void send(const link::Command& command) override;
  std::vector<link::Telemetry> receive(std::chrono::milliseconds timeout) override;
  std::string describe() const override;

 private:
  void serve();

  SimulatedRover rover_;
  std::chrono::milliseconds heartbeat_period_;
  RoverObserver observer_;
  std::mutex mutex_;
  std::condition_variable commands_ready_, telemetry_ready_;
  std::deque<link::Command> commands_;
  std::vector<link::Telemetry> telemetry_;
  bool stopping_ = false;
  std::thread worker_;  // last: starts once everything above exists
};

}  // namespace ambler::rover
