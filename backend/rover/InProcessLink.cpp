#include "rover/InProcessLink.h"

#include <utility>

namespace ambler::rover {

InProcessLink::InProcessLink(const SimulatedRoverConfig& config, SimulatedRoverOptions options,
                             std::chrono::milliseconds heartbeat_period, RoverObserver observer)
    : rover_(config, std::move(options)),
      heartbeat_period_(heartbeat_period),
      observer_(std::move(observer)),
      worker_([this] { serve(); }) {}

InProcessLink::~InProcessLink() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  commands_ready_.notify_all();
  worker_.join();
}

void InProcessLink::send(const link::Command& command) {
  {
    std::lock_guard lock(mutex_);
    commands_.push_back(command);
  }
  commands_ready_.notify_one();
}

std::vector<link::Telemetry> InProcessLink::receive(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  telemetry_ready_.wait_for(lock, timeout, [&] { return !telemetry_.empty(); });
  return std::exchange(telemetry_, {});
}

std::string InProcessLink::describe() const {
  return "simulator in this process, rover " + std::to_string(rover_.roverId());
}

// The rover's loop on this thread; commands come from the queue.
void InProcessLink::serve() {
  RoverLoopIo io;
  io.receive = [this](std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    commands_ready_.wait_for(lock, timeout, [&] { return stopping_ || !commands_.empty(); });
    std::vector<Incoming> batch;
    for (auto& c : commands_) batch.push_back({std::move(c), {}});
    commands_.clear();
    return batch;
  };
  io.publish = [this](const link::Telemetry& t) {
    {
      std::lock_guard lock(mutex_);
      telemetry_.push_back(t);
    }
    telemetry_ready_.notify_all();
  };
  io.stopping = [this] {
    std::lock_guard lock(mutex_);
    return stopping_;
  };
  io.handled = observer_;
  runRoverLoop(rover_, heartbeat_period_, io);
}

}  // namespace ambler::rover
