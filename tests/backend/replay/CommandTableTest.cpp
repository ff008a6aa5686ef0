#include "replay/CommandTable.h"

#include <gtest/gtest.h>

namespace ambler::replay {
namespace {

link::Command command(std::uint64_t sequence, link::CommandBody body) {
  return {.rover_id = 1,
          .operator_id = "alice",
          .sequence = sequence,
          .body = std::move(body),
          .hmac = {}};
}

link::Telemetry ack(std::uint64_t sequence, bool accepted, std::string reason = {}) {
  return {1, 0.0, link::CommandAck{"alice", 0, sequence, accepted, std::move(reason)}};
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
  table.received(3.6, {1, 0.0, link::Heartbeat{7, true, "Hold from bob", {}, {}}});
  table.received(3.7, {1, 0.0, link::Heartbeat{8, true, "Hold from bob", {}, {}}});
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
  EXPECT_EQ(rows[4].what, "answer to command 99 of alice@0000000000000000");
  EXPECT_EQ(rows[5].what, "holds");  // once, not per heartbeat
  EXPECT_EQ(rows[5].reason, "Hold from bob");
  EXPECT_EQ(rows[6].what, "rejected proposal 7");
  EXPECT_EQ(rows[6].reason, "foot near the trench");
}

TEST(CommandTable, DecisionsAndEventsReadAsSentencesWithUnits) {
  CommandTable table;
  table.decided({1.0, "alice", 4, missionlog::Verdict::kApproved,
                 R"({"proposal":4,"leg":2,"body_advance":0.5234567,"min_csp_margin_m":0.15123,)"
                 R"("interlocks":"passed","foothold_m":[1.2345,-3.4,-0.051]})"});
  table.decided({2.0, "alice", 5, missionlog::Verdict::kRejected,
                 R"({"proposal":5,"leg":-1,"body_advance":0.3,"min_csp_margin_m":0.09,)"
                 R"("interlocks":"stability: margin 0.09 m","reason":"rejected by alice"})"});
  table.decided({3.0, "alice", 0, missionlog::Verdict::kApproved,
                 R"({"grasp":{"centre_m":"0.1,0.2,0.03","size_m":"0.05,0.04,0.03",)"
                 R"("rms_m":0.0012,"points":812}})"});
  table.decided({4.0, "bob", 6, missionlog::Verdict::kEdited, "{not json"});
  table.noted(5.0, "step suspended: no step to propose");
  // A turn in place: body_advance is in radians there, so the sentence
  // takes the body's move and turn instead.
  table.decided({6.0, "alice", 8, missionlog::Verdict::kApproved,
                 R"({"proposal":8,"leg":3,"body_advance":0.2618,"body_move_m":0.004,)"
                 R"("body_turn_deg":15.0012,"min_csp_margin_m":0.2,"interlocks":"passed",)"
                 R"("foothold_m":[1.0,2.0,0.1]})"});

  const auto& rows = table.rows();
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[0].reason,
            "leg 2 to (1.23, -3.40, -0.05) m, body advance 0.52 m, least stability margin 0.15 m, "
            "interlocks passed");
  EXPECT_EQ(rows[1].reason,
            "body move only, body advance 0.30 m, least stability margin 0.09 m, interlock "
            "failed: stability: margin 0.09 m; reason: rejected by alice");
  EXPECT_EQ(rows[2].what, "approved grasp");
  EXPECT_EQ(rows[2].reason,
            "rock at (0.10, 0.20, 0.03) m, size (0.05, 0.04, 0.03) m, fit rms 1.2 mm, 812 points");
  EXPECT_EQ(rows[3].reason, "{not json");  // not the gate's: shown as it is
  EXPECT_EQ(rows[5].reason,
            "leg 3 to (1.00, 2.00, 0.10) m, body moves 0.00 m, turns 15.0 deg, least stability "
            "margin 0.20 m, interlocks passed");
  EXPECT_EQ(rows[4].who, "ground");
  EXPECT_EQ(rows[4].what, "step suspended: no step to propose");
}

}  // namespace
}  // namespace ambler::replay
