#include "replay/MissionTimeline.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "executive/WalkExecutive.h"
#include "io/Json.h"
#include "link/Codec.h"
#include "missionlog/MissionLog.h"
#include "terrain/Merge.h"

namespace ambler::replay {

namespace {

// The grid the executive mapped on, from its first logged map; the
// executive's default when the log has none.
GridSpec mapGrid(const std::vector<missionlog::LoggedProduct>& products,
                 const std::filesystem::path& log) {
  for (const auto& p : products) {
    if (p.kind != "elevation_map") continue;
    nlohmann::json json;
    try {
      json = nlohmann::json::parse(p.parameters);
    } catch (const nlohmann::json::exception& e) {
      throw io::FormatError(log.string() + ": elevation_map parameters: " + e.what());
    }
    const io::JsonFields fields(json, log.string() + ": elevation_map parameters");
    GridSpec grid = io::readGridPlacement(fields);
    grid.rows = fields.integer("rows"), grid.cols = fields.integer("cols");
    if (grid.rows <= 0 || grid.cols <= 0 || grid.rows * std::int64_t(grid.cols) > 50'000'000)
      fields.fail("rows", "a map of " + std::to_string(grid.rows) + " x " +
                              std::to_string(grid.cols) + " cells is not plausible");
    return grid;
  }
  const executive::ExecutiveOptions defaults;
  return GridSpec::covering(defaults.map_extent, defaults.map_resolution_m);
}

// The correction the executive placed each scan with, by the scan's
// telemetry time, and whether it merged the scan at all; scans without one
// were mapped where the rover said.
struct LoggedCorrection {
  executive::PoseCorrection correction;
  bool merged = true;
};

std::map<double, LoggedCorrection> loggedCorrections(
    const std::vector<missionlog::LoggedProduct>& products, const std::filesystem::path& log) {
  std::map<double, LoggedCorrection> out;
  for (const auto& p : products) {
    if (p.kind != "pose_correction") continue;
    const std::string context =
        log.string() + ": pose_correction at " + std::to_string(p.time_s) + " s";
    nlohmann::json json;
    try {
      json = nlohmann::json::parse(p.parameters);
    } catch (const nlohmann::json::exception& e) {
      throw io::FormatError(context + ": " + e.what());
    }
    const io::JsonFields f(json, context);
    const bool merged = !json.contains("merged") || json["merged"] != false;
    out[f.number("range_image_time_s")] = {
        {{f.number("shift_x_m"), f.number("shift_y_m")}, f.number("yaw_rad"), f.number("dz_m")},
        merged};
  }
  return out;
}

executive::Task loggedTask(const missionlog::LoggedProduct& p, const std::filesystem::path& log) {
  const std::string context = log.string() + ": task at " + std::to_string(p.time_s) + " s";
  try {
    const auto json = nlohmann::json::parse(p.parameters);
    const io::JsonFields f(json, context);
    executive::Task t;
    t.name = f.string("name");
    t.kind = executive::kindFromName(f.string("kind"));
    t.status = executive::statusFromName(f.string("status"));
    t.started_s = f.number("started_s"), t.ended_s = f.number("ended_s");
    return t;
  } catch (const nlohmann::json::exception& e) {
    throw io::FormatError(context + ": " + e.what());
  } catch (const std::invalid_argument& e) {
    throw io::FormatError(context + ": " + e.what());
  }
}

// A walk's event as WalkSession logs it: {"what": "..."}.
std::string loggedEvent(const missionlog::LoggedProduct& p, const std::filesystem::path& log) {
  const std::string context = log.string() + ": event at " + std::to_string(p.time_s) + " s";
  try {
    return io::JsonFields(nlohmann::json::parse(p.parameters), context).string("what");
  } catch (const nlohmann::json::exception& e) {
    throw io::FormatError(context + ": " + e.what());
  }
}

executive::StepProposal loggedProposal(const missionlog::LoggedProduct& p,
                                       const std::filesystem::path& log) {
  try {
    return executive::proposalFromRecord(p.parameters);
  } catch (const std::invalid_argument& e) {
    throw io::FormatError(log.string() + ": proposal at " + std::to_string(p.time_s) +
                          " s: " + e.what());
  }
}

}  // namespace

MissionTimeline MissionTimeline::build(const std::filesystem::path& log, const Progress& progress) {
  const missionlog::MissionLogReader reader(log);
  MissionTimeline t;
  const auto summary = reader.summary();
  t.mission_ = summary.mission;
  t.first_s_ = summary.first_s, t.last_s_ = summary.last_s;

  CommandTable table;
  std::vector<Timed> scans;
  for (const auto& m : reader.messages(-INFINITY, INFINITY)) {
    try {
      if (m.direction == missionlog::Direction::kToRover) {
        table.sent(m.time_s, link::decodeCommand(m.payload));
        continue;
      }
      auto telemetry = link::decodeTelemetry(m.payload);
      const auto& body = telemetry.body;
      if (std::holds_alternative<sensor::RangeImage>(body)) {
        scans.push_back({m.time_s, std::move(telemetry)});
      } else if (std::holds_alternative<link::LegState>(body) ||
                 std::holds_alternative<link::BodyState>(body)) {
        t.states_.push_back({m.time_s, std::move(telemetry)});
      } else {
        if (std::holds_alternative<link::CommandAck>(body)) t.marks_.push_back(m.time_s);
        table.received(m.time_s, telemetry);
      }
    } catch (const link::DecodeError&) {
      ++t.unreadable_;
    }
  }
  for (const auto& d : reader.decisions()) {
    table.decided(d);
    t.marks_.push_back(d.time_s);
    if (d.verdict != missionlog::Verdict::kEdited) t.decided_s_.emplace(d.proposal, d.time_s);
  }
  const auto products = reader.products();
  for (const auto& p : products) {
    if (p.kind == "event") table.noted(p.time_s, loggedEvent(p, log));
    if (p.kind == "proposal") t.proposals_.emplace_back(p.time_s, loggedProposal(p, log));
  }
  t.rows_ = table.takeRows();
  std::stable_sort(t.rows_.begin(), t.rows_.end(),
                   [](const LogRow& a, const LogRow& b) { return a.time_s < b.time_s; });

  for (const auto& p : products)
    if (p.kind == "task") t.tasks_.push_back(loggedTask(p, log));

  // krotkov1989 §3 then cmu-1990 'LTM Merger', exactly as WalkExecutive,
  // each scan placed by the correction the executive logged for it.
  terrain::ElevationMap map(mapGrid(products, log));
  const auto corrections = loggedCorrections(products, log);
  const int total = int(scans.size());
  for (int i = 0; i < total; ++i) {
    if (progress && !progress(i, total)) throw Cancelled();
    const auto& scan = scans[std::size_t(i)].message;
    sensor::RangeImage image = std::get<sensor::RangeImage>(scan.body);
    const auto c = corrections.find(scan.time_s);
    if (c != corrections.end())
      image.sensor_to_world = c->second.correction.transform() * image.sensor_to_world;
    if (c == corrections.end() || c->second.merged) terrain::mergeScan(map, image);
    t.maps_.push_back({scans[std::size_t(i)].time_s, map, std::move(image)});
    t.marks_.push_back(scans[std::size_t(i)].time_s);
  }
  if (progress) progress(total, total);
  std::sort(t.marks_.begin(), t.marks_.end());
  return t;
}

const MapAfterScan* MissionTimeline::mapAt(double time_s) const {
  const auto it = std::upper_bound(maps_.begin(), maps_.end(), time_s,
                                   [](double t, const MapAfterScan& m) { return t < m.time_s; });
  return it == maps_.begin() ? nullptr : &*std::prev(it);
}

executive::RoverReport MissionTimeline::roverAt(double time_s) const {
  executive::RoverReport report;
  for (const auto& s : states_) {
    if (s.time_s > time_s) break;
    report.take(s.message);
  }
  return report;
}

std::vector<executive::RoverSample> MissionTimeline::samples(const gait::RoverModel& model) const {
  std::vector<executive::RoverSample> out;
  executive::RoverReport report;
  for (const auto& s : states_) {
    report.take(s.message);
    if (auto sample = report.sample(model, s.time_s)) out.push_back(std::move(*sample));
  }
  return out;
}

std::optional<executive::StepProposal> MissionTimeline::pendingAt(double time_s) const {
  const auto after = std::upper_bound(
      proposals_.begin(), proposals_.end(), time_s,
      [](double t, const std::pair<double, executive::StepProposal>& p) { return t < p.first; });
  if (after == proposals_.begin()) return std::nullopt;
  const auto& [proposed_s, proposal] = *std::prev(after);
  const auto [first, last] = decided_s_.equal_range(proposal.id);
  for (auto d = first; d != last; ++d)
    if (d->second >= proposed_s && d->second <= time_s) return std::nullopt;
  return proposal;
}

std::size_t MissionTimeline::rowsUpTo(double time_s) const {
  return std::size_t(std::upper_bound(rows_.begin(), rows_.end(), time_s,
                                      [](double t, const LogRow& r) { return t < r.time_s; }) -
                     rows_.begin());
}

}  // namespace ambler::replay
