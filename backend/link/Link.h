#pragma once

// What a console sees of a rover (QGroundControl's LinkInterface): commands
// go out, telemetry comes in. The simulator in this process, ambler-sim or
// a rover over DDS, and a mission log replayed are links the rest of the
// program cannot tell apart.

#include <chrono>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "link/Messages.h"

namespace ambler::link {

class LinkError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Link {
 public:
  virtual ~Link() = default;
  // Hands a command to the rover, which answers with a CommandAck. Throws
  // LinkError when this link cannot carry commands (a replayed log).
  virtual void send(const Command& command) = 0;
  // Telemetry that arrived since the last call, oldest first; waits up to
  // `timeout` while none has.
  virtual std::vector<Telemetry> receive(std::chrono::milliseconds timeout) = 0;
  // For the status bar: "simulator in this process", "DDS domain 0, rover 1", ...
  virtual std::string describe() const = 0;
};

// How fresh the rover's data is: the ground station shows a link as stale,
// with the age of the last data, once nothing has arrived for a while.
class LinkHealth {
 public:
  explicit LinkHealth(double stale_after_s = 3.0) : stale_after_s_(stale_after_s) {}
  void heard(double now_s) { last_s_ = now_s; }
  // Seconds since the last telemetry; none before the first.
  std::optional<double> ageS(double now_s) const {
    if (!last_s_) return std::nullopt;
    return now_s - *last_s_;
  }
  const std::optional<double>& lastHeardS() const { return last_s_; }
  bool stale(double now_s) const {
    const auto age = ageS(now_s);
    return !age || *age > stale_after_s_;
  }

 private:
  double stale_after_s_;
  std::optional<double> last_s_;
};

// Any link, noting in a LinkHealth when the rover last spoke, and showing
// an observer (a console's command table) each command as it leaves and
// each message as it arrives.
struct LinkObserver {
  std::function<void(const Command&)> sent;
  std::function<void(const Telemetry&)> received;
};

class WatchedLink : public Link {
 public:
  WatchedLink(Link& inner, LinkHealth& health, std::function<double()> clock,
              LinkObserver observer = {})
      : inner_(inner), health_(health), clock_(std::move(clock)), observer_(std::move(observer)) {}
  void send(const Command& command) override {
    inner_.send(command);
    if (observer_.sent) observer_.sent(command);
  }
  std::vector<Telemetry> receive(std::chrono::milliseconds timeout) override {
    auto in = inner_.receive(timeout);
    if (!in.empty()) health_.heard(clock_());
    if (observer_.received)
      for (const auto& m : in) observer_.received(m);
    return in;
  }
  std::string describe() const override { return inner_.describe(); }

 private:
  Link& inner_;
  LinkHealth& health_;
  std::function<double()> clock_;
  LinkObserver observer_;
};

}  // namespace ambler::link
