#pragma once

// A mission log turned into what the operator saw, at any time: the local
// terrain map after each scan (recomputed from the logged range images as
// the executive computed it: locus method, then merged), where the rover
// reported its body and legs, and the commands, acknowledgements and
// decisions as one table. Built once when a log is opened; scrubbing is
// then a lookup.

#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "executive/ApprovalGate.h"
#include "executive/ReportedStance.h"
#include "executive/TaskTree.h"
#include "gait/RoverModel.h"
#include "replay/CommandTable.h"
#include "sensor/RangeImage.h"
#include "terrain/ElevationMap.h"

namespace ambler::replay {

// The terrain map as it stood after one scan.
struct MapAfterScan {
  double time_s = 0.0;  // when the range image arrived
  terrain::ElevationMap map;
  sensor::RangeImage scan;  // placed by the correction logged for it
};

// done of total scans mapped; return false to stop building.
using Progress = std::function<bool(int done, int total)>;

// Building was stopped through Progress.
struct Cancelled : std::exception {
  const char* what() const noexcept override { return "building the timeline was cancelled"; }
};

class MissionTimeline {
 public:
  // Reads the log (missionlog::LogError when it cannot) and maps every range
  // image in it on the grid the executive logged with its maps.
  static MissionTimeline build(const std::filesystem::path& log, const Progress& progress = {});

  const std::string& mission() const { return mission_; }
  double firstS() const { return first_s_; }
  double lastS() const { return last_s_; }
  const std::vector<MapAfterScan>& maps() const { return maps_; }
  // The map after the last scan at or before `time_s`; none before the first.
  const MapAfterScan* mapAt(double time_s) const;
  // The latest body and leg states at or before `time_s`.
  executive::RoverReport roverAt(double time_s) const;
  // The rover's stance after each report that completed or changed it.
  std::vector<executive::RoverSample> samples(const gait::RoverModel& model) const;
  const std::vector<LogRow>& rows() const { return rows_; }
  // How many rows are at or before `time_s`.
  std::size_t rowsUpTo(double time_s) const;
  // The executive's tasks as logged when each ended (cmu-1990 fig. 7).
  const std::vector<executive::Task>& tasks() const { return tasks_; }
  // The step waiting for the operator at `time_s` (proposed, or edited,
  // at or before it and not yet approved or rejected), as the log keeps it.
  std::optional<executive::StepProposal> pendingAt(double time_s) const;
  // Times worth stepping to: each scan, each decision, each move's answer.
  const std::vector<double>& marks() const { return marks_; }
  // Messages in the log that could not be decoded (left out).
  long unreadable() const { return unreadable_; }

 private:
  struct Timed {
    double time_s;
    link::Telemetry message;
  };
  std::string mission_;
  double first_s_ = 0.0, last_s_ = 0.0;
  std::vector<MapAfterScan> maps_;
  std::vector<Timed> states_;  // leg and body states in time order
  std::vector<LogRow> rows_;
  std::vector<double> marks_;
  std::vector<executive::Task> tasks_;
  std::vector<std::pair<double, executive::StepProposal>> proposals_;  // in time order
  // When each proposal id was approved or rejected (ids restart with each
  // walk a log holds).
  std::multimap<std::uint64_t, double> decided_s_;
  long unreadable_ = 0;
};

}  // namespace ambler::replay
