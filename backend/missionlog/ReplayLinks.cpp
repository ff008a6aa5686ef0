#include "missionlog/ReplayLinks.h"

#include <algorithm>
#include <map>
#include <thread>

#include "link/Codec.h"
#include "link/Signing.h"

namespace ambler::missionlog {

namespace {

// What a newer message of the same kind replaces: the type, and the leg for
// leg states.
std::pair<std::size_t, int> kindOf(const link::Telemetry& t) {
  const auto* leg = std::get_if<link::LegState>(&t.body);
  return {t.body.index(), leg ? leg->leg : -1};
}

}  // namespace

std::uint64_t firstSequenceFromClock() { return std::uint64_t(link::utcNowS() * 1e6); }

RecordingLink::RecordingLink(link::Link& inner, MissionLog& log, std::function<double()> clock)
    : inner_(inner), log_(log), clock_(std::move(clock)) {}

void RecordingLink::send(const link::Command& command) {
  log_.record(clock_(), command);
  inner_.send(command);
}

std::vector<link::Telemetry> RecordingLink::receive(std::chrono::milliseconds timeout) {
  auto messages = inner_.receive(timeout);
  log_.record(clock_(), messages);
  return messages;
}

std::string RecordingLink::describe() const { return inner_.describe() + ", recorded"; }

LogReplayLink::LogReplayLink(const std::filesystem::path& path) : path_(path) {
  const MissionLogReader reader(path);
  for (auto& m : reader.messages(-INFINITY, INFINITY)) {
    if (m.direction != Direction::kFromRover) continue;
    try {
      entries_.push_back({m.time_s, link::decodeTelemetry(m.payload)});
    } catch (const link::DecodeError&) {
      ++unreadable_;
    }
  }
  if (!entries_.empty()) first_s_ = entries_.front().time_s, last_s_ = entries_.back().time_s;
  anchor_s_ = first_s_;
}

void LogReplayLink::send(const link::Command&) {
  throw link::LinkError("a replayed mission log cannot command a rover");
}

std::string LogReplayLink::describe() const { return "replay of " + path_.string(); }

double LogReplayLink::positionS() const {
  const double elapsed = std::chrono::duration<double>(Clock::now() - anchor_wall_).count();
  return std::min(anchor_s_ + speed_ * elapsed, std::max(last_s_, anchor_s_));
}

void LogReplayLink::play(double speed) {
  anchor_s_ = positionS(), anchor_wall_ = Clock::now();
  speed_ = std::max(speed, 0.0);
}

void LogReplayLink::pause() { play(0.0); }

void LogReplayLink::step() {
  pause();
  if (next_ < entries_.size()) anchor_s_ = entries_[next_].time_s;
}

void LogReplayLink::seek(double time_s) {
  anchor_s_ = std::clamp(time_s, first_s_, last_s_), anchor_wall_ = Clock::now();
  next_ = std::size_t(std::upper_bound(entries_.begin(), entries_.end(), anchor_s_,
                                       [](double t, const Entry& e) { return t < e.time_s; }) -
                      entries_.begin());
  snapshot_pending_ = true;
}

std::vector<link::Telemetry> LogReplayLink::receive(std::chrono::milliseconds timeout) {
  std::vector<link::Telemetry> out;
  if (snapshot_pending_) {
    snapshot_pending_ = false;
    std::map<std::pair<std::size_t, int>, std::size_t> latest;
    for (std::size_t i = 0; i < next_; ++i) latest[kindOf(entries_[i].message)] = i;
    std::vector<std::size_t> order;
    for (const auto& [kind, i] : latest) order.push_back(i);
    std::sort(order.begin(), order.end());
    for (auto i : order) out.push_back(entries_[i].message);
    return out;
  }
  const auto deadline = Clock::now() + timeout;
  while (true) {
    const double now = positionS();
    while (next_ < entries_.size() && entries_[next_].time_s <= now)
      out.push_back(entries_[next_++].message);
    if (!out.empty() || Clock::now() >= deadline) return out;
    std::this_thread::sleep_for(
        std::min<Clock::duration>(std::chrono::milliseconds(5), deadline - Clock::now()));
  }
}

}  // namespace ambler::missionlog
