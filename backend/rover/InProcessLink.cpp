#include "rover/InProcessLink.h"

#include <utility>

namespace ambler::rover {

InProcessLink::InProcessLink(const walk::WalkConfig& config, SimulatedRoverOptions options,
                             std::chrono::milliseconds heartbeat_period)
    : rover_(config, std::move(options)),
      heartbeat_period_(heartbeat_period),
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

double InProcessLink::roverTimeS() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void InProcessLink::publish(std::vector<link::Telemetry> messages) {
  {
    std::lock_guard lock(mutex_);
    for (auto& m : messages) telemetry_.push_back(std::move(m));
  }
  telemetry_ready_.notify_all();
}

// The rover's loop: the full state once, then commands as they come and a
// heartbeat whenever a period passes.
void InProcessLink::serve() {
  publish(rover_.state(roverTimeS()));
  auto next_heartbeat = std::chrono::steady_clock::now();
  while (true) {
    std::unique_lock lock(mutex_);
    commands_ready_.wait_until(lock, next_heartbeat,
                               [&] { return stopping_ || !commands_.empty(); });
    if (stopping_) return;
    std::deque<link::Command> batch;
    batch.swap(commands_);
    lock.unlock();
    for (const auto& command : batch) publish(rover_.handle(command, roverTimeS()));
    if (std::chrono::steady_clock::now() >= next_heartbeat) {
      publish({rover_.heartbeat(roverTimeS())});
      next_heartbeat += heartbeat_period_;
    }
  }
}

}  // namespace ambler::rover
