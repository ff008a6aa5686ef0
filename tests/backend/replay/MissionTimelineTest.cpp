#include "replay/MissionTimeline.h"

#include <gtest/gtest.h>
#include <memory>

#include "InstalledConfig.h"
#include "TempDir.h"
#include "executive/WalkExecutive.h"
#include "io/FormatError.h"
#include "missionlog/ReplayLinks.h"
#include "rover/InProcessLink.h"
#include "rover/SimulatedRover.h"

namespace ambler::replay {
namespace {

using namespace std::chrono_literals;

using testing_config::ground;
using testing_config::simulator;

link::OperatorKey alice() { return {"alice", std::vector<std::uint8_t>(32, 7)}; }

// Layers equal cell for cell, NaN where the other is NaN.
bool sameLayer(const terrain::Layer& a, const terrain::Layer& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    const float x = a.data()[i], y = b.data()[i];
    if (!(x == y || (std::isnan(x) && std::isnan(y)))) return false;
  }
  return true;
}

bool endedFirst(const executive::Task& a, const executive::Task& b) {
  return std::tie(a.ended_s, a.started_s, a.name) < std::tie(b.ended_s, b.started_s, b.name);
}

// A two-step walk in the simulator, auto-approved, recorded in a mission
// log; what the executive mapped after each scan is kept as the truth.
class MissionTimelineTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>();
    log_path_ = *dir_ / "timeline.sqlite";
    missionlog::MissionLog log(log_path_, "timeline test");
    rover::SimulatedRoverOptions rover_options;
    rover_options.operators = {alice()};
    rover::InProcessLink rover(simulator(), rover_options, 200ms);
    double now = 1000.0;
    missionlog::RecordingLink recording(rover, log, [&] { return now; });
    link::CommandSigner signer(alice());
    executive::ApprovalGate gate([&](const missionlog::Decision& d) { log.record(d); });
    gate.setMode(executive::ApprovalMode::kAutoApprove);
    executive::ExecutiveOptions options;
    options.steps = 2;
    executive::WalkExecutive walk(recording, signer, gate, ground(), options);
    walk.onProduct([&](double t, const std::string& kind, const std::string& parameters) {
      log.recordProduct(t, kind, parameters);
      if (kind == "elevation_map") maps_.push_back(walk.map());
    });
    walk.start(now);
    for (int i = 0; i < 2000 && walk.phase() != executive::Phase::kDone; ++i)
      walk.poll(now += 0.05, 10ms);
    ASSERT_EQ(walk.phase(), executive::Phase::kDone);
    final_ = *walk.report().stance(ground().model);  // as the rover reported it
    // The replay must place the scans as the executive did, by a correction.
    ASSERT_GT(walk.correction().shift.norm(), 0.0);
    for (const auto& task : walk.tasks().tasks())
      if (task.status != executive::TaskStatus::kActive &&
          task.status != executive::TaskStatus::kWaiting)
        tasks_.push_back(task);
    std::sort(tasks_.begin(), tasks_.end(), endedFirst);
  }
  static void TearDownTestSuite() { dir_.reset(); }

  static inline std::unique_ptr<TempDir> dir_;
  static inline std::filesystem::path log_path_;
  static inline std::vector<terrain::ElevationMap> maps_;
  static inline gait::Stance final_;
  static inline std::vector<executive::Task> tasks_;  // ended, in order
};

TEST_F(MissionTimelineTest, MapsEachScanAsTheExecutiveDid) {
  std::vector<std::pair<int, int>> progress;
  const auto timeline = MissionTimeline::build(log_path_, [&](int done, int total) {
    progress.emplace_back(done, total);
    return true;
  });
  ASSERT_GE(maps_.size(), 2u);
  ASSERT_EQ(timeline.maps().size(), maps_.size());
  for (std::size_t i = 0; i < maps_.size(); ++i) {
    const auto& got = timeline.maps()[i].map;
    EXPECT_EQ(got.grid().rows, maps_[i].grid().rows);
    EXPECT_EQ(got.knownCount(), maps_[i].knownCount()) << "scan " << i;
    EXPECT_TRUE(sameLayer(got.layer(terrain::layer::kElevation),
                          maps_[i].layer(terrain::layer::kElevation)))
        << "scan " << i;
    EXPECT_TRUE(
        sameLayer(got.layer(terrain::layer::kSigma), maps_[i].layer(terrain::layer::kSigma)));
  }
  // Progress counts scans from 0 to all of them.
  ASSERT_EQ(progress.size(), maps_.size() + 1);
  EXPECT_EQ(progress.front(), std::make_pair(0, int(maps_.size())));
  EXPECT_EQ(progress.back(), std::make_pair(int(maps_.size()), int(maps_.size())));
  EXPECT_EQ(timeline.unreadable(), 0);
  EXPECT_EQ(timeline.mission(), "timeline test");
  // The module timing of the walk: each task the executive ended, in order.
  auto logged = timeline.tasks();
  std::sort(logged.begin(), logged.end(), endedFirst);
  ASSERT_EQ(logged.size(), tasks_.size());
  for (std::size_t i = 0; i < tasks_.size(); ++i) {
    EXPECT_EQ(logged[i].name, tasks_[i].name);
    EXPECT_EQ(logged[i].kind, tasks_[i].kind);
    EXPECT_EQ(logged[i].status, tasks_[i].status);
    EXPECT_DOUBLE_EQ(logged[i].started_s, tasks_[i].started_s);
    EXPECT_DOUBLE_EQ(logged[i].ended_s, tasks_[i].ended_s);
  }
}

TEST_F(MissionTimelineTest, ScrubbingGivesTheMapAndTheRoverOfThatTime) {
  const auto timeline = MissionTimeline::build(log_path_);
  const auto& maps = timeline.maps();
  EXPECT_EQ(timeline.mapAt(maps[0].time_s - 1e-3), nullptr);
  EXPECT_EQ(timeline.mapAt(maps[0].time_s), &maps[0]);
  EXPECT_EQ(timeline.mapAt((maps[0].time_s + maps[1].time_s) / 2), &maps[0]);
  EXPECT_EQ(timeline.mapAt(timeline.lastS()), &maps.back());
  // Later scans know more of the ground.
  EXPECT_GT(maps.back().map.knownCount(), maps.front().map.knownCount());

  const auto end = timeline.roverAt(timeline.lastS()).stance(ground().model);
  ASSERT_TRUE(end);
  EXPECT_NEAR((end->body.xy - final_.body.xy).norm(), 0.0, 1e-9);
  for (int leg = 0; leg < gait::kLegCount; ++leg)
    EXPECT_NEAR((end->feet[leg] - final_.feet[leg]).norm(), 0.0, 1e-9) << leg;
  const auto start = timeline.roverAt(maps[0].time_s).stance(ground().model);
  ASSERT_TRUE(start);
  EXPECT_GT(end->body.xy.y() - start->body.xy.y(), 0.2);  // two steps forward (+y)
  EXPECT_FALSE(timeline.roverAt(timeline.firstS() - 1).body);
  const auto history = timeline.samples(ground().model);
  ASSERT_FALSE(history.empty());
  EXPECT_NEAR((history.back().stance.body.xy - final_.body.xy).norm(), 0.0, 1e-9);
  // The force sensors' loads come back from the log: the feet carry the weight.
  double load_n = 0;
  for (double f : history.back().force_n) load_n += f;
  EXPECT_NEAR(load_n, ground().model.mass_kg * 9.81, 1.0);
}

TEST_F(MissionTimelineTest, TheTableAnswersEachCommandAndShowsEachDecision) {
  const auto timeline = MissionTimeline::build(log_path_);
  const auto& rows = timeline.rows();
  int scans = 0, moves = 0, approvals = 0;
  for (const auto& r : rows) {
    EXPECT_NE(r.what.find("GroundHeartbeat"), 0u) << "accepted heartbeats are noise";
    if (r.what.rfind("AcquireScan range scanner", 0) == 0) {
      ++scans;
      EXPECT_EQ(r.outcome, "accepted");
    }
    if (r.what.rfind("LegMove leg ", 0) == 0 || r.what.rfind("BodyMove (", 0) == 0) {
      ++moves;
      EXPECT_EQ(r.who, "alice");
      EXPECT_EQ(r.outcome, "accepted") << r.what << ": " << r.reason;
    }
    if (r.what.rfind("approved proposal", 0) == 0) {
      ++approvals;
      EXPECT_EQ(r.who, "auto-approve");
    }
  }
  EXPECT_EQ(scans, int(timeline.maps().size()));
  EXPECT_EQ(approvals, 2);
  EXPECT_GE(moves, 2);
  EXPECT_TRUE(std::is_sorted(rows.begin(), rows.end(),
                             [](const LogRow& a, const LogRow& b) { return a.time_s < b.time_s; }));
  EXPECT_EQ(timeline.rowsUpTo(timeline.firstS() - 1), 0u);
  EXPECT_EQ(timeline.rowsUpTo(timeline.lastS()), rows.size());
  EXPECT_TRUE(std::is_sorted(timeline.marks().begin(), timeline.marks().end()));
}

// Auto-approved steps never wait: each is approved at the time it is
// proposed, so no time of the walk shows one pending.
TEST_F(MissionTimelineTest, AnAutoApprovedStepIsNeverShownWaiting) {
  const auto timeline = MissionTimeline::build(log_path_);
  for (double t = timeline.firstS(); t <= timeline.lastS(); t += 0.05)
    EXPECT_FALSE(timeline.pendingAt(t).has_value()) << t;
}

// A step waits from its proposal to its decision, with the figures logged;
// ids restart with each walk in the same log.
TEST(MissionTimeline, AStepWaitsFromItsProposalToItsDecision) {
  const TempDir dir;
  const auto path = dir / "pending.sqlite";
  executive::StepProposal p;
  p.id = 1;
  p.plan.leg = 2;
  p.interlocks.checks = {{"plan", true, "ok"}};
  {
    missionlog::MissionLog log(path, "pending");
    log.recordProduct(1.0, "proposal", executive::proposalRecord(p));
    log.record({3.0, "alice", 1, missionlog::Verdict::kApproved, "{}"});
    p.plan.leg = 4;  // the next walk's first step, id 1 again
    log.recordProduct(5.0, "proposal", executive::proposalRecord(p));
    log.record({6.0, "alice", 1, missionlog::Verdict::kRejected, "{}"});
  }
  const auto timeline = MissionTimeline::build(path);
  EXPECT_FALSE(timeline.pendingAt(0.5));
  ASSERT_TRUE(timeline.pendingAt(2.0));
  EXPECT_EQ(timeline.pendingAt(2.0)->plan.leg, 2);
  EXPECT_EQ(timeline.pendingAt(2.0)->interlocks.checks.front().detail, "ok");
  EXPECT_FALSE(timeline.pendingAt(4.0));
  ASSERT_TRUE(timeline.pendingAt(5.5));
  EXPECT_EQ(timeline.pendingAt(5.5)->plan.leg, 4);
  EXPECT_FALSE(timeline.pendingAt(6.5));
}

TEST_F(MissionTimelineTest, BuildingCanBeCancelled) {
  EXPECT_THROW(MissionTimeline::build(log_path_, [](int done, int) { return done < 1; }),
               Cancelled);
}

TEST(MissionTimeline, TheWalksEventsAreRowsOfTheTableAtTheirTime) {
  const TempDir dir;
  const auto path = dir / "events.sqlite";
  {
    missionlog::MissionLog log(path, "events");
    log.record(1.0, link::Telemetry{1, 1.0, link::Heartbeat{1, false, {}, {}, {}}});
    log.recordProduct(2.0, "event", R"({"what": "step suspended: step rejected by the operator"})");
    log.recordProduct(3.0, "event", R"({"what": "resumed: scanning and planning again"})");
  }
  const auto timeline = MissionTimeline::build(path);
  ASSERT_EQ(timeline.rows().size(), 2u);
  EXPECT_EQ(timeline.rows()[0].who, "ground");
  EXPECT_EQ(timeline.rows()[0].what, "step suspended: step rejected by the operator");
  EXPECT_EQ(timeline.rowsUpTo(2.5), 1u);

  const auto bad = dir / "bad-event.sqlite";
  {
    missionlog::MissionLog log(bad, "bad event");
    log.recordProduct(2.0, "event", R"({"said": 3})");
  }
  try {
    MissionTimeline::build(bad);
    FAIL();
  } catch (const io::FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("event at 2"), std::string::npos) << e.what();
  }
}

TEST(MissionTimeline, BadLogsAreNamedNotCrashedOn) {
  const TempDir dir;
  EXPECT_THROW(MissionTimeline::build(dir / "missing.sqlite"), missionlog::LogError);

  const auto path = dir / "bad.sqlite";
  {
    missionlog::MissionLog log(path, "bad");
    log.record(1.0, link::Telemetry{1, 1.0, link::Heartbeat{1, false, {}, {}, {}}});
    log.recordProduct(2.0, "elevation_map", "{\"origin_x\": 0, \"resolution\": 0.1}");
    missionlog::Database db(path, true);
    db.exec(
        "INSERT INTO messages(time_s, direction, type, rover_id, payload) "
        "VALUES (1.5, 'from_rover', 'BodyState', 1, x'0102')");
  }
  try {
    MissionTimeline::build(path);
    FAIL();
  } catch (const io::FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("elevation_map parameters"), std::string::npos)
        << e.what();
  }
  {
    missionlog::Database db(path, true);
    db.exec("DELETE FROM products");
  }
  const auto timeline = MissionTimeline::build(path);  // the truncated message left out
  EXPECT_EQ(timeline.unreadable(), 1);
  EXPECT_TRUE(timeline.maps().empty());
}

}  // namespace
}  // namespace ambler::replay
