#include "replay/CommandTable.h"

#include <gtest/gtest.h>

namespace ambler::replay {
namespace {

link::Command command(std::uint64_t sequence, link::CommandBody body) {
  return {1, "alice", sequence, 0.0, std::move(body), std::nullopt};
}

link::Telemetry ack(std::uint64_t sequence, bool accepted, std::string reason = {}) {
  return {1, 0.0, link::CommandAck{"alice", sequence, accepted, std::move(reason)}};
}

TEST(CommandTable, EachCommandIsAnsweredInItsOwnRow) {
  CommandTable table;
  table.sent(1.0, command(1, link::AcquireScan{}));
  table.sent(2.0, command(2, link::BodyMove{0.0, 0.45, 0.0, 0.0}));
  table.sent(2.5, command(3, link::GroundHeartbeat{}));
  table.sent(2.6, command(4, link::GroundHeartbeat{}));
  table.sent(3.0, command(5, link::LegMove{2, {{}, {}, {}}}));
  table.received(3.1, ack(2, false, "holding (link lost): send Resume first"));
  table.received(3.2, ack(1, true));
  table.received(3.3, ack(3, true));  // an accepted heartbeat: nothing to show
  table.received(3.4, ack(4, false, "stale sequence"));
  table.received(3.5, ack(99, true));  // answers nothing this console sent
  table.received(3.6, {1, 0.0, link::Heartbeat{7, true, "Hold from bob"}});
  table.received(3.7, {1, 0.0, link::Heartbeat{8, true, "Hold from bob"}});
  table.decided({4.0, "alice", 7, missionlog::Verdict::kRejected, "foot near the trench"});

  const auto& rows = table.rows();
  ASSERT_EQ(rows.size(), 7u);
  EXPECT_EQ(rows[0].what, "AcquireScan range scanner");
  EXPECT_EQ(rows[0].outcome, "accepted");
  EXPECT_EQ(rows[1].what, "BodyMove (0.000, 0.450) m, 0.000 deg");
  EXPECT_EQ(rows[1].outcome, "refused");
  EXPECT_EQ(rows[1].reason, "holding (link lost): send Resume first");
  EXPECT_EQ(rows[2].what, "LegMove leg 2, 3 waypoints");
  EXPECT_EQ(rows[2].outcome, "no answer");
  EXPECT_EQ(rows[3].what, "GroundHeartbeat");  // refused: shown at the time it was sent
  EXPECT_DOUBLE_EQ(rows[3].time_s, 2.6);
  EXPECT_EQ(rows[4].who, "rover");
  EXPECT_EQ(rows[4].what, "answer to an unknown command 99");
  EXPECT_EQ(rows[5].what, "holds");  // once, not per heartbeat
  EXPECT_EQ(rows[5].reason, "Hold from bob");
  EXPECT_EQ(rows[6].what, "rejected proposal 7");
  EXPECT_EQ(rows[6].reason, "foot near the trench");
}

}  // namespace
}  // namespace ambler::replay
