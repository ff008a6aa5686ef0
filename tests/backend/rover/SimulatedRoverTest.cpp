#include "rover/SimulatedRover.h"

#include <gtest/gtest.h>

#include "InstalledConfig.h"
#include "TempDir.h"
#include "io/Dtm.h"
#include "link/Codec.h"
#include "rover/InProcessLink.h"
#include "sim/TerrainFamilies.h"

namespace ambler::rover {
namespace {

using testing_config::ground;
using testing_config::simulator;

link::OperatorKey alice() { return {"alice", std::vector<std::uint8_t>(32, 7)}; }

SimulatedRoverOptions options() {
  SimulatedRoverOptions o;
  o.rover_id = 2;
  o.operators = {alice()};
  o.scanned_area = {-6, -6, 6, 12};
  return o;
}

link::Command command(link::CommandBody body, link::CommandSigner* signer) {
  link::Command c;
  c.rover_id = 2;
  c.body = std::move(body);
  if (signer) signer->sign(c);
  return c;
}

const link::CommandAck& ackOf(const std::vector<link::Telemetry>& out) {
  return std::get<link::CommandAck>(out.at(0).body);
}

TEST(SimulatedRover, ASignedBodyMoveIsExecutedAndReported) {
  SimulatedRover rover(simulator(), options());
  link::CommandSigner signer(alice());
  const auto start = rover.world().rover().truth().body.xy;
  const auto out = rover.handle(command(link::BodyMove{0.0, 0.3, 0.0, 0.0}, &signer), 1.0);
  ASSERT_TRUE(ackOf(out).accepted) << ackOf(out).reason;
  EXPECT_EQ(ackOf(out).sequence, 1u);
  ASSERT_EQ(out.size(), 1u + gait::kLegCount + 1);  // ack, six legs, body
  const auto& body = std::get<link::BodyState>(out.back().body);
  // Forward is +y; execution noise is about 1 cm per metre.
  EXPECT_NEAR(body.y_m - start.y(), 0.3, 0.02);
  EXPECT_EQ(out.back().rover_id, 2u);
}

// With a time scale a move is acknowledged when it is taken on, with a
// body state that says it moves, and its outcome comes once its modelled
// time, scaled, has passed; meanwhile other moves and scans are refused, a
// Hold is not.
TEST(SimulatedRover, WithATimeScaleAMoveReportsItsOutcomeWhenItsTimeIsUp) {
  auto o = options();
  o.time_scale = 0.5;
  SimulatedRover rover(simulator(), o);
  link::CommandSigner signer(alice());
  const gait::BodyPose start = rover.estimate().body;
  auto out = rover.handle(command(link::BodyMove{0.0, 0.3, 0.0, 0.0}, &signer), 1.0);
  ASSERT_EQ(out.size(), 2u);
  ASSERT_TRUE(ackOf(out).accepted) << ackOf(out).reason;
  const auto& moving = std::get<link::BodyState>(out[1].body);
  EXPECT_TRUE(moving.moving);
  EXPECT_EQ(out[1].time_s, 1.0);
  // Where the rover stood when the move began: the outcome says where it ended.
  EXPECT_EQ(moving.x_m, start.xy.x());
  EXPECT_EQ(moving.y_m, start.xy.y());
  EXPECT_EQ(moving.heading_rad, start.heading_rad);
  const double due = 1.0 + 0.5 * rover.lastMove().duration_s;
  EXPECT_GT(due, 5.0);  // 0.3 m at 2 m/min
  EXPECT_TRUE(rover.finished(due - 0.01).empty());
  out = rover.handle(command(link::AcquireScan{}, &signer), 1.5);
  EXPECT_EQ(ackOf(out).reason, "busy: BodyMove 1 under way");
  out = rover.handle(command(link::Hold{}, &signer), 2.0);
  EXPECT_TRUE(ackOf(out).accepted) << ackOf(out).reason;
  out = rover.handle(command(link::Resume{}, &signer), 2.5);
  ASSERT_EQ(out.size(), 2u);  // the ack and a heartbeat: the state comes with the outcome
  EXPECT_TRUE(ackOf(out).accepted) << ackOf(out).reason;
  EXPECT_FALSE(std::get<link::Heartbeat>(out[1].body).holding);
  const auto outcome = rover.finished(due);
  ASSERT_EQ(outcome.size(), gait::kLegCount + 1u);  // six legs, body
  for (const auto& t : outcome) EXPECT_EQ(t.time_s, due);
  const auto& ended = std::get<link::BodyState>(outcome.back().body);
  EXPECT_FALSE(ended.moving);
  EXPECT_NEAR(ended.y_m - start.xy.y(), 0.3, 0.02);
  EXPECT_TRUE(rover.finished(due + 100).empty());  // once
}

TEST(SimulatedRover, RefusedCommandsMoveNothingAndSayWhy) {
  SimulatedRover rover(simulator(), options());
  link::CommandSigner signer(alice());
  const auto before = rover.world().rover().truth().body.xy;

  auto out = rover.handle(command(link::BodyMove{0.0, 0.3, 0.0, 0.0}, nullptr), 1.0);
  EXPECT_FALSE(ackOf(out).accepted);
  EXPECT_EQ(ackOf(out).reason, "unsigned command");
  EXPECT_EQ(out.size(), 1u);

  out = rover.handle(command(link::BodyMove{0.0, 2.5, 0.0, 0.0}, &signer), 2.0);
  EXPECT_EQ(ackOf(out).reason, "body advance 2.50 m over the 1.50 m limit");

  const auto legs = rover.state(0.0);
  gait::LegJoints far = std::get<link::LegState>(legs[0].body).joints;
  far.extension_m = 2.8;
  out = rover.handle(command(link::LegMove{0, {far}}, &signer), 3.0);
  EXPECT_EQ(ackOf(out).reason, "leg 0 waypoint 1: extension 2.80 m outside 0.50-2.50 m");

  out = rover.handle(command(link::Grasp{0, 0, 0, 0, 0.3}, &signer), 4.0);
  EXPECT_EQ(ackOf(out).reason, "this rover has no manipulator");

  EXPECT_EQ((rover.world().rover().truth().body.xy - before).norm(), 0.0);
}

// The link's security: unsigned, forged, tampered, replayed and
// reordered commands are each refused, and nothing moves.
TEST(SimulatedRover, ForgedReplayedAndReorderedCommandsMoveNothing) {
  SimulatedRover rover(simulator(), options());
  link::CommandSigner signer(alice());
  auto first = command(link::BodyMove{0, 0.2, 0, 0}, &signer);
  auto second = command(link::BodyMove{0, 0.2, 0, 0}, &signer);
  ASSERT_TRUE(ackOf(rover.handle(second, 1.0)).accepted);  // sequence 2 goes first
  const auto truth = [&] { return rover.world().rover().truth(); };
  const auto before = truth();

  link::CommandSigner forger({"alice", std::vector<std::uint8_t>(32, 9)}, 10);
  auto tampered = command(link::BodyMove{0, 0.2, 0, 0}, &signer);
  std::get<link::BodyMove>(tampered.body).y_m = 1.0;
  gait::LegJoints lifted = std::get<link::LegState>(rover.state(0.0)[0].body).joints;
  lifted.vertical_m -= 0.3;
  const std::vector<std::pair<link::Command, std::string>> bad{
      {command(link::BodyMove{0, 0.2, 0, 0}, nullptr), "unsigned command"},
      {command(link::LegMove{0, {lifted}}, &forger), "bad signature for operator \"alice\""},
      {tampered, "bad signature for operator \"alice\""},
      {second, "replayed command: sequence 2 already accepted"},
      {first, "out of order: sequence 1 after 2"},
  };
  double t = 2.0;
  for (const auto& [c, reason] : bad) {
    const auto out = rover.handle(c, t += 1.0);
    ASSERT_EQ(out.size(), 1u) << reason;  // the NACK, and no state: nothing changed
    EXPECT_FALSE(ackOf(out).accepted);
    EXPECT_EQ(ackOf(out).reason, reason);
  }
  EXPECT_EQ((truth().body.xy - before.body.xy).norm(), 0.0);
  EXPECT_EQ(truth().body.heading_rad, before.body.heading_rad);
  for (int i = 0; i < gait::kLegCount; ++i)
    EXPECT_EQ(truth().feet[std::size_t(i)], before.feet[std::size_t(i)]) << "leg " << i;
}

const link::Heartbeat& heartbeatOf(const std::vector<link::Telemetry>& out) {
  for (const auto& t : out)
    if (const auto* h = std::get_if<link::Heartbeat>(&t.body)) return *h;
  throw std::runtime_error("no heartbeat");
}

TEST(SimulatedRover, HoldsWhenTheGroundFallsSilentUntilResumed) {
  auto o = options();
  o.link_timeout_s = 3.0;
  SimulatedRover rover(simulator(), o);
  link::CommandSigner signer(alice());
  EXPECT_TRUE(rover.watchLink(100.0).empty());  // no console yet: nothing to lose
  ASSERT_TRUE(ackOf(rover.handle(command(link::BodyMove{0, 0.2, 0, 0}, &signer), 101.0)).accepted);
  // A signed heartbeat keeps the watchdog fed and is not acknowledged.
  EXPECT_TRUE(rover.handle(command(link::GroundHeartbeat{}, &signer), 103.5).empty());
  EXPECT_TRUE(rover.watchLink(106.4).empty());
  // An unsigned one (a watching console) does not feed it.
  EXPECT_FALSE(ackOf(rover.handle(command(link::GroundHeartbeat{}, nullptr), 106.45)).accepted);
  const auto hold = rover.watchLink(106.6);
  ASSERT_EQ(hold.size(), 1u);
  EXPECT_TRUE(heartbeatOf(hold).holding);
  EXPECT_EQ(heartbeatOf(hold).hold_reason,
            "link lost: no command or heartbeat from the ground for 3.1 s");
  EXPECT_TRUE(rover.watchLink(107.0).empty());  // announced once

  const auto held_at = rover.world().rover().truth().body.xy;
  auto out = rover.handle(command(link::BodyMove{0, 0.2, 0, 0}, &signer), 110.0);
  EXPECT_EQ(ackOf(out).reason,
            "holding (link lost: no command or heartbeat from the ground for 3.1 s): send Resume "
            "first");
  EXPECT_TRUE(ackOf(rover.handle(command(link::AcquireScan{}, &signer), 110.5)).accepted);
  EXPECT_EQ((rover.world().rover().truth().body.xy - held_at).norm(), 0.0);

  out = rover.handle(command(link::Resume{}, &signer), 111.0);
  EXPECT_TRUE(ackOf(out).accepted);
  EXPECT_FALSE(heartbeatOf(out).holding);
  EXPECT_EQ(out.size(), 1u + 1u + gait::kLegCount + 1u);  // ack, heartbeat, the whole state
  EXPECT_TRUE(ackOf(rover.handle(command(link::BodyMove{0, 0.2, 0, 0}, &signer), 112.0)).accepted);

  // An operator's Hold holds the same way.
  out = rover.handle(command(link::Hold{}, &signer), 113.0);
  EXPECT_EQ(heartbeatOf(out).hold_reason, "Hold from alice");
  EXPECT_FALSE(ackOf(rover.handle(command(link::BodyMove{0, 0.2, 0, 0}, &signer), 114.0)).accepted);
}

TEST(SimulatedRover, ACommandDelayedPastItsValidityWindowIsRefusedOnBoard) {
  SimulatedRover rover(simulator(), options());
  link::CommandSigner signer(alice(), 1, {.validity_s = 2.0});
  const auto move = command(link::BodyMove{0, 0.2, 0, 0}, &signer);
  const auto before = rover.world().rover().truth().body.xy;
  const auto out = rover.handle(move, move.time_s + 2.5);  // held 2.5 s on the way
  EXPECT_EQ(ackOf(out).reason,
            "arrived 0.50 s after its validity window closed (signed 2.50 s ago, valid for "
            "2.00 s)");
  EXPECT_EQ(out.size(), 1u);
  EXPECT_EQ((rover.world().rover().truth().body.xy - before).norm(), 0.0);
}

// The rover keeps sequences in memory only: after a restart, a recorded
// command must still not move it again.
TEST(SimulatedRover, ACommandPlayedAgainAfterARoverRestartIsRefused) {
  link::CommandSigner signer(alice());
  link::Command recorded;
  {
    SimulatedRover rover(simulator(), options());
    recorded = command(link::BodyMove{0, 0.2, 0, 0}, &signer);
    ASSERT_TRUE(ackOf(rover.handle(recorded, recorded.time_s + 0.1)).accepted);
    EXPECT_NE(ackOf(rover.handle(recorded, recorded.time_s + 0.2)).reason.find("replayed"),
              std::string::npos);
  }
  SimulatedRover restarted(simulator(), options());
  const auto reason = ackOf(restarted.handle(recorded, recorded.time_s + 0.3)).reason;
  EXPECT_NE(reason.find("before this rover's link started (a command from before a restart)"),
            std::string::npos)
      << reason;
  // The console goes on with new commands.
  EXPECT_TRUE(
      ackOf(restarted.handle(command(link::BodyMove{0, 0.2, 0, 0}, &signer), link::utcNowS()))
          .accepted);
}

TEST(SimulatedRover, OnlyTheConsoleInCommandMovesTheRoverAndAnyConsoleMayHoldIt) {
  auto o = options();
  o.operators.push_back({"bob", std::vector<std::uint8_t>(32, 8)});
  o.link_timeout_s = 3.0;
  SimulatedRover rover(simulator(), o);
  link::CommandSigner a(alice()), b(o.operators[1]);
  const double t = link::utcNowS();
  ASSERT_TRUE(ackOf(rover.handle(command(link::BodyMove{0, 0.2, 0, 0}, &a), t)).accepted);
  EXPECT_EQ(heartbeatOf({rover.heartbeat(t)}).authority, a.console());
  EXPECT_EQ(rover.takeAuthorityChange(), a.console() + " took command authority");

  auto out = rover.handle(command(link::BodyMove{0, 0.2, 0, 0}, &b), t + 0.1);
  EXPECT_EQ(ackOf(out).reason, b.console() + " does not hold command authority (" + a.console() +
                                   " does): send RequestAuthority and wait for a hand-over");
  // The watching console's heartbeats do not keep the rover going for the
  // commanding one.
  EXPECT_TRUE(rover.handle(command(link::GroundHeartbeat{}, &b), t + 2.0).empty());
  EXPECT_TRUE(heartbeatOf(rover.watchLink(t + 3.2)).holding);
  EXPECT_EQ(rover.takeAuthorityChange(), a.console() + " lost command authority");
  EXPECT_FALSE(rover.authority().held());

  // Back in command, then any console may stop the rover.
  ASSERT_TRUE(ackOf(rover.handle(command(link::Resume{}, &a), t + 4.0)).accepted);
  EXPECT_EQ(rover.authority().holder(), a.console());
  out = rover.handle(command(link::Hold{}, &b), t + 4.1);
  EXPECT_TRUE(ackOf(out).accepted);
  EXPECT_EQ(heartbeatOf(out).hold_reason, "Hold from bob");

  // The hand-over: bob asks, alice hands over, and bob is in command.
  ASSERT_TRUE(ackOf(rover.handle(command(link::RequestAuthority{}, &b), t + 4.2)).accepted);
  EXPECT_EQ(heartbeatOf({rover.heartbeat(t + 4.2)}).authority_request, b.console());
  ASSERT_TRUE(ackOf(rover.handle(command(link::HandOver{b.console()}, &a), t + 4.3)).accepted);
  EXPECT_EQ(rover.takeAuthorityChange(),
            a.console() + " handed command authority to " + b.console());
  EXPECT_TRUE(ackOf(rover.handle(command(link::Resume{}, &b), t + 4.4)).accepted);
  EXPECT_FALSE(ackOf(rover.handle(command(link::Resume{}, &a), t + 4.5)).accepted);
}

// After an outage a console's late command takes authority back while the
// rover holds; if that console then dies, the silence must hand authority
// on, or no other console could ever resume.
TEST(SimulatedRover, AConsoleFallingSilentWhileTheRoverHoldsLosesCommandAuthority) {
  auto o = options();
  o.operators.push_back({"bob", std::vector<std::uint8_t>(32, 8)});
  o.link_timeout_s = 3.0;
  SimulatedRover rover(simulator(), o);
  link::CommandSigner a(alice()), b(o.operators[1], 1, {.validity_s = 60.0});
  const double t = link::utcNowS();
  ASSERT_TRUE(ackOf(rover.handle(command(link::BodyMove{0, 0.2, 0, 0}, &a), t)).accepted);
  ASSERT_TRUE(heartbeatOf(rover.watchLink(t + 3.2)).holding);
  EXPECT_EQ(rover.takeAuthorityChange(), a.console() + " lost command authority");

  // Alice's scan, sent before she heard of the hold, arrives late.
  ASSERT_TRUE(ackOf(rover.handle(command(link::AcquireScan{}, &a), t + 3.4)).accepted);
  EXPECT_EQ(rover.authority().holder(), a.console());
  ASSERT_TRUE(ackOf(rover.handle(command(link::RequestAuthority{}, &b), t + 3.5)).accepted);
  EXPECT_FALSE(ackOf(rover.handle(command(link::Resume{}, &b), t + 3.6)).accepted);

  // Alice is gone: once she has been silent for the timeout (and twice the
  // link's delay), bob, who asked, holds authority; the rover still holds.
  EXPECT_TRUE(rover.watchLink(t + 5.0).empty());
  const auto lapsed = rover.watchLink(t + 30.0);
  ASSERT_EQ(lapsed.size(), 1u);
  EXPECT_TRUE(heartbeatOf(lapsed).holding);
  EXPECT_EQ(heartbeatOf(lapsed).authority, b.console());
  EXPECT_EQ(rover.takeAuthorityChange(), a.console() + " lost command authority; " + b.console() +
                                             " took command authority (it had asked)");
  EXPECT_TRUE(rover.watchLink(t + 31.0).empty());  // announced once
  const auto resumed = rover.handle(command(link::Resume{}, &b), t + 31.0);
  EXPECT_TRUE(ackOf(resumed).accepted) << ackOf(resumed).reason;
}

TEST(SimulatedRover, AcquireScanSendsARangeImageFromWhereTheRoverIs) {
  SimulatedRover rover(simulator(), options());
  link::CommandSigner signer(alice());
  const auto out = rover.handle(command(link::AcquireScan{}, &signer), 1.0);
  ASSERT_TRUE(ackOf(out).accepted);
  ASSERT_EQ(out.size(), 2u);
  const auto& image = std::get<sensor::RangeImage>(out[1].body);
  EXPECT_GT(image.returnCount(), image.rows() * image.cols() / 2);
  const auto& body = rover.world().rover().truth().body;
  EXPECT_NEAR(image.sensor_to_world.translation().x(), body.xy.x(), 1e-9);
}

// The simulator walks a real terrain model: a crater field written as a
// GeoTIFF DTM at easting 5000, northing 2000 is the world the rover stands
// in, centred on the window, and its scanner sees it. The striper, which
// needs a procedural course, says so.
TEST(SimulatedRover, WalksATerrainModelLoadedThroughGdal) {
  TempDir dir;
  const sim::ProceduralTerrain craters(sim::makeFamilyTerrain(sim::TerrainFamily::kCraterField, 5));
  const GridSpec dtm_grid{4970.0, 1970.0, 0.1, 600, 600};
  io::FloatImage z(600, 600);
  for (int r = 0; r < 600; ++r)
    for (int c = 0; c < 600; ++c) {
      const auto p = dtm_grid.cellCenter(r, c);
      z(r, c) = float(craters.height(p.x() - 5000.0, p.y() - 2000.0));
    }
  io::writeGeoTiff(dir / "dtm.tif", z, dtm_grid, "m");
  auto o = options();
  o.dtm = sim::DtmSource{dir / "dtm.tif", {.width = 60.0, .height = 60.0, .resolution = 0.1}};
  SimulatedRover rover(simulator(), o);
  const auto& world = rover.world().terrain();
  for (const double x : {-4.95, 0.05, 7.25})
    for (const double y : {-3.05, 2.15, 9.95})
      EXPECT_NEAR(world.height(x, y), craters.height(x, y), 1e-5) << x << ", " << y;
  link::CommandSigner signer(alice());
  const auto out = rover.handle(command(link::AcquireScan{}, &signer), 1.0);
  ASSERT_TRUE(ackOf(out).accepted) << ackOf(out).reason;
  const auto& image = std::get<sensor::RangeImage>(out[1].body);
  EXPECT_GT(image.returnCount(), image.rows() * image.cols() / 2);
  const auto striper =
      rover.handle(command(link::AcquireScan{link::ScanSensor::kLightStriper}, &signer), 2.0);
  EXPECT_FALSE(ackOf(striper).accepted);
  EXPECT_NE(ackOf(striper).reason.find("terrain model"), std::string::npos);
}

// A real rover knows its pose only from its encoders: the simulated one
// reports the body it dead-reckons (and tags its scans with it), which
// drifts from the truth with the execution noise; without noise the two
// agree.
TEST(SimulatedRover, ReportsItsOwnDeadReckonedPoseNotTheTruth) {
  SimulatedRoverConfig exact = simulator();
  exact.noise = {.encoder_rotation_rad = 0,
                 .encoder_extension_m = 0,
                 .encoder_vertical_m = 0,
                 .placement_m = 0,
                 .body_m = 0,
                 .body_rad = 0,
                 .slip_probability = 0,
                 .ground_creep_m = 0,
                 .ground_creep_rad = 0};
  for (const bool noisy : {true, false}) {
    SimulatedRover rover(noisy ? simulator() : exact, options());
    link::CommandSigner signer(alice());
    for (int k = 0; k < 10; ++k) {
      const double dy = k % 2 ? -0.25 : 0.25;
      const auto out = rover.handle(command(link::BodyMove{0.0, dy, 0.0, 0.0}, &signer), k);
      ASSERT_TRUE(ackOf(out).accepted) << ackOf(out).reason;
      const auto& reported = std::get<link::BodyState>(out.back().body);
      EXPECT_EQ(reported.x_m, rover.estimate().body.xy.x());
      EXPECT_EQ(reported.y_m, rover.estimate().body.xy.y());
    }
    const auto& truth = rover.world().rover().truth().body;
    const double drift = (rover.estimate().body.xy - truth.xy).norm();
    if (noisy) {
      EXPECT_GT(drift, 1e-4);  // 2.5 m walked at about 1 cm per metre of body error
      EXPECT_LT(drift, 0.05);
    } else {
      EXPECT_LT(drift, 1e-9);
    }
    const auto scan = rover.handle(command(link::AcquireScan{}, &signer), 20.0);
    const auto& image = std::get<sensor::RangeImage>(scan.at(1).body);
    EXPECT_EQ(image.sensor_to_world.matrix(),
              rover.world().mountPose(rover.estimate().body).matrix());
  }
}

// The striper image holds the ground ahead: its points lie on the course's
// surface (to the striper's 0.5 mm noise plus the marching tolerance) in
// front of the body.
TEST(SimulatedRover, AcquireScanWithTheStriperSendsTheGroundAhead) {
  SimulatedRover rover(simulator(), options());
  link::CommandSigner signer(alice());
  const auto out =
      rover.handle(command(link::AcquireScan{link::ScanSensor::kLightStriper}, &signer), 1.0);
  ASSERT_TRUE(ackOf(out).accepted) << ackOf(out).reason;
  ASSERT_EQ(out.size(), 2u);
  const auto& image = std::get<sensor::StriperImage>(out[1].body);
  EXPECT_EQ(sensor::findProblem(image), "");
  EXPECT_GT(image.pointCount(), image.rows() * image.cols() / 2);
  const auto& terrain = rover.world().terrain();
  const auto& body = rover.world().rover().truth().body;
  double worst = 0.0;
  for (int r = 0; r < image.rows(); r += 8)
    for (int c = 0; c < image.cols(); c += 8) {
      if (!image.hasPoint(r, c)) continue;
      const Eigen::Vector3d p = image.point(r, c);
      worst = std::max(worst, std::abs(p.z() - terrain.height(p.x(), p.y())));
      EXPECT_GT(body.toBody(Eigen::Vector2d(p.head<2>())).y(), 1.5);  // ahead of the body centre
    }
  EXPECT_LT(worst, 0.01);
  // Through the byte form unchanged.
  const auto back =
      std::get<sensor::StriperImage>(link::decodeTelemetry(link::encode(out[1])).body);
  EXPECT_EQ(back.z, image.z);
  EXPECT_EQ(back.camera.camera_to_world.matrix(), image.camera.camera_to_world.matrix());
}

// The same exchange through the link: a console sends, the rover's thread
// answers; heartbeats keep coming while the console waits.
TEST(InProcessLink, CommandsGoOutAndTelemetryComesBack) {
  InProcessLink link(simulator(), options(), std::chrono::milliseconds(20));
  link::CommandSigner signer(alice());
  link.send(command(link::BodyMove{0.0, 0.2, 0.0, 0.0}, &signer));
  link.send(command(link::BodyMove{0.0, 0.2, 0.0, 0.0}, nullptr));
  std::vector<link::CommandAck> acks;
  int heartbeats = 0, bodies = 0;
  for (int i = 0; i < 100 && (acks.size() < 2 || heartbeats < 2); ++i)
    for (const auto& t : link.receive(std::chrono::milliseconds(50))) {
      if (const auto* ack = std::get_if<link::CommandAck>(&t.body)) acks.push_back(*ack);
      heartbeats += std::holds_alternative<link::Heartbeat>(t.body);
      bodies += std::holds_alternative<link::BodyState>(t.body);
    }
  ASSERT_EQ(acks.size(), 2u);
  EXPECT_TRUE(acks[0].accepted);
  EXPECT_FALSE(acks[1].accepted);
  EXPECT_EQ(acks[1].reason, "unsigned command");
  EXPECT_GE(heartbeats, 2);
  EXPECT_EQ(bodies, 2);  // the state at start and after the one move
  EXPECT_NE(link.describe().find("rover 2"), std::string::npos);
}

}  // namespace
}  // namespace ambler::rover
