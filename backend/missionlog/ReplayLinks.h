#pragma once

// The mission log at both ends of a link: RecordingLink writes everything a
// console sends and receives through any link to the log before passing it
// on; LogReplayLink plays a log back as if it were the rover, so every view
// works the same on a replay.

#include <chrono>
#include <filesystem>
#include <functional>

#include "link/Link.h"
#include "link/Signing.h"
#include "missionlog/MissionLog.h"

namespace ambler::missionlog {

// The first sequence number of a console: the ground's UTC clock
// (link::utcNowS, the log's time_s) in microseconds,
// so that numbers grow across console restarts (a rover refuses one it has
// seen).
std::uint64_t firstSequenceFromClock();

class RecordingLink : public link::Link {
 public:
  RecordingLink(link::Link& inner, MissionLog& log, std::function<double()> clock = link::utcNowS);
  // Logged first: a command is on disk before it leaves.
  void send(const link::Command& command) override;
  std::vector<link::Telemetry> receive(std::chrono::milliseconds timeout) override;
  std::string describe() const override;

 private:
  link::Link& inner_;
  MissionLog& log_;
  std::function<double()> clock_;
};

// Plays back the telemetry of a log on its own timeline: paused at the
// start until play(); step() and seek() move through it. Commands cannot be
// sent. After seek(t), the next receive() gives the latest message of each
// kind (each leg, the body, the last scan, ...) at or before t, then
// playback continues from there.
class LogReplayLink : public link::Link {
 public:
  explicit LogReplayLink(const std::filesystem::path& path);

  void send(const link::Command& command) override;
  std::vector<link::Telemetry> receive(std::chrono::milliseconds timeout) override;
  std::string describe() const override;

  void play(double speed = 1.0);
  void pause();
  // To the next message and no further; paused.
  void step();
  void seek(double time_s);
  double positionS() const;
  double firstS() const { return first_s_; }
  double lastS() const { return last_s_; }
  bool playing() const { return speed_ > 0; }
  long unreadable() const { return unreadable_; }

 private:
  using Clock = std::chrono::steady_clock;
  struct Entry {
    double time_s;
    link::Telemetry message;
  };
  std::filesystem::path path_;
  std::vector<Entry> entries_;  // from the rover, in time order
  double first_s_ = 0.0, last_s_ = 0.0;
  std::size_t next_ = 0;   // the first entry not yet delivered
  double anchor_s_ = 0.0;  // log time at `anchor_wall_`
  Clock::time_point anchor_wall_ = Clock::now();
  double speed_ = 0.0;  // 0: paused
  bool snapshot_pending_ = false;
  long unreadable_ = 0;
};

}  // namespace ambler::missionlog
