#include "missionlog/ReplayLinks.h"

#include <gtest/gtest.h>

#include <deque>

#include "TempDir.h"

namespace ambler::missionlog {
namespace {

// A rover that answers nothing and sends what the test queues.
class ScriptedLink : public link::Link {
 public:
  std::deque<link::Telemetry> to_send;
  std::vector<link::Command> sent;
  void send(const link::Command& c) override { sent.push_back(c); }
  std::vector<link::Telemetry> receive(std::chrono::milliseconds) override {
    std::vector<link::Telemetry> out(to_send.begin(), to_send.end());
    to_send.clear();
    return out;
  }
  std::string describe() const override { return "scripted"; }
};

link::Telemetry body(double y) { return {1, y, link::BodyState{0.0, y, 2.4, 0.0, false}}; }
link::Telemetry leg(int i, double extension) {
  return {1, 0.0, link::LegState{i, {0.0, extension, 2.0}, true}};
}

class ReplayTest : public ::testing::Test {
 protected:
  // A session recorded through a RecordingLink with a clock the test sets:
  // bodies at t = 10, 11, 12, 13, legs 0 and 1 at 10.5 and 12.5, one command.
  void SetUp() override {
    path_ = dir_ / "replay.sqlite";
    MissionLog log(path_, "replay test");
    ScriptedLink rover;
    double now = 0;
    RecordingLink recording(rover, log, [&] { return now; });
    auto at = [&](double t, link::Telemetry m) {
      now = t;
      rover.to_send.push_back(std::move(m));
      recording.receive(std::chrono::milliseconds(0));
    };
    at(10.0, body(0.0));
    at(10.5, leg(0, 1.0));
    at(10.5, leg(1, 1.1));
    at(11.0, body(0.5));
    now = 11.5;
    link::Command c;
    c.body = link::Hold{};
    recording.send(c);
    ASSERT_EQ(rover.sent.size(), 1u);
    at(12.0, body(1.0));
    at(12.5, leg(0, 1.5));
    at(13.0, body(1.5));
  }
  TempDir dir_;
  std::filesystem::path path_;
};

TEST_F(ReplayTest, TheRecordingHoldsEveryMessageBothWays) {
  const Summary s = MissionLogReader(path_).summary();
  EXPECT_EQ(s.from_rover.at("BodyState"), 4);
  EXPECT_EQ(s.from_rover.at("LegState"), 3);
  EXPECT_EQ(s.to_rover.at("Hold"), 1);
  EXPECT_DOUBLE_EQ(s.durationS(), 3.0);
}

TEST_F(ReplayTest, StepSeekAndPlayWalkTheTimeline) {
  LogReplayLink replay(path_);
  EXPECT_DOUBLE_EQ(replay.firstS(), 10.0);
  EXPECT_DOUBLE_EQ(replay.lastS(), 13.0);
  EXPECT_THROW(replay.send(link::Command{}), link::LinkError);

  // Paused at the start: only what is stamped at the very start.
  auto got = replay.receive(std::chrono::milliseconds(20));
  ASSERT_EQ(got.size(), 1u);
  EXPECT_TRUE(replay.receive(std::chrono::milliseconds(20)).empty());
  replay.step();  // both legs share 10.5
  got = replay.receive(std::chrono::milliseconds(20));
  ASSERT_EQ(got.size(), 2u);
  EXPECT_DOUBLE_EQ(replay.positionS(), 10.5);

  // Scrub to 12.7: the body at 12.0 and the latest of each leg.
  replay.seek(12.7);
  got = replay.receive(std::chrono::milliseconds(20));
  ASSERT_EQ(got.size(), 3u);
  double leg0 = 0, leg1 = 0, body_y = -1;
  for (const auto& t : got) {
    if (const auto* l = std::get_if<link::LegState>(&t.body))
      (l->leg == 0 ? leg0 : leg1) = l->joints.extension_m;
    if (const auto* b = std::get_if<link::BodyState>(&t.body)) body_y = b->y_m;
  }
  EXPECT_DOUBLE_EQ(leg0, 1.5);
  EXPECT_DOUBLE_EQ(leg1, 1.1);
  EXPECT_DOUBLE_EQ(body_y, 1.0);

  // Play fast to the end: the one message left.
  replay.play(100.0);
  got = replay.receive(std::chrono::milliseconds(500));
  ASSERT_EQ(got.size(), 1u);
  EXPECT_DOUBLE_EQ(std::get<link::BodyState>(got[0].body).y_m, 1.5);
  EXPECT_EQ(replay.unreadable(), 0);
}

}  // namespace
}  // namespace ambler::missionlog
