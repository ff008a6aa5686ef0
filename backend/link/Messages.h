#pragma once

// The messages between a ground station and a rover (or the simulator):
// telemetry from the rover, commands from the ground. Plain structs; the
// codec (Codec.h) gives them one byte form for signing, logging and the wire.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "gait/RoverModel.h"
#include "sensor/RangeImage.h"
#include "sensor/StriperImage.h"

namespace ambler::link {

// ---- telemetry (rover -> ground) ----

// The rover is alive, and whether it holds: after a Hold command, or on
// its own when the ground fell silent (link loss), it refuses every motion
// until a Resume.
struct Heartbeat {
  std::uint64_t count = 0;
  bool holding = false;
  std::string hold_reason;  // empty unless holding
  // The console that holds command authority ("alice@00c0ffee3f09a1c2",
  // consoleName()) and one asking for it; empty: none.
  std::string authority;
  std::string authority_request;
};

// One leg as its encoders and force sensor report it.
struct LegState {
  int leg = 0;
  gait::LegJoints joints;
  bool contact = false;
  double force_n = 0.0;  // vertical load on the foot [N]
};

// The body's pose in the world as the rover believes it (dead reckoning).
struct BodyState {
  double x_m = 0.0, y_m = 0.0, z_m = 0.0;
  double heading_rad = 0.0;
  bool moving = false;
};

// The rover's answer to one command: accepted, or refused and why.
struct CommandAck {
  std::string operator_id;
  std::uint64_t console_id = 0;  // with the operator: whose command
  std::uint64_t sequence = 0;
  bool accepted = false;
  std::string reason;  // empty when accepted
};

using TelemetryBody = std::variant<Heartbeat, LegState, BodyState, CommandAck, sensor::RangeImage,
                                   sensor::StriperImage>;

struct Telemetry {
  std::uint32_t rover_id = 0;
  double time_s = 0.0;  // rover clock
  TelemetryBody body;
};

// ---- commands (ground -> rover) ----

// cmu-1990 'Real-time control': joint waypoints, all joints arriving together.
struct LegMove {
  int leg = 0;
  std::vector<gait::LegJoints> waypoints;
};

// Translation in the body frame and rotation about the vertical; the link
// plane rises by raise_m on the way.
struct BodyMove {
  double x_m = 0.0, y_m = 0.0;
  double rotation_rad = 0.0;
  double raise_m = 0.0;
};

// Clam-shell grasp: centre in the world, jaws along `yaw_rad`.
struct Grasp {
  double x_m = 0.0, y_m = 0.0, z_m = 0.0;
  double yaw_rad = 0.0;
  double opening_m = 0.0;
};

// Which sensor: the laser range scanner (a RangeImage comes back) or the
// light-striper for rock sampling (a StriperImage).
enum class ScanSensor : std::uint8_t { kRangeScanner = 0, kLightStriper = 1 };

struct AcquireScan {
  ScanSensor sensor = ScanSensor::kRangeScanner;
};

// Stop every motion now and stay still until a Resume.
struct Hold {};

// The console is alive (signed like every command, so a watching console
// cannot keep the rover going for a commanding one that died). Only
// refusals are acknowledged.
struct GroundHeartbeat {};

// End a hold; motion commands are accepted again.
struct Resume {};

// Ask for command authority: granted at once when no console holds it,
// else announced in the Heartbeat until the holder hands over.
struct RequestAuthority {};

// From the console holding authority: give it to the console whose
// request is pending (the two ends of an explicit exchange).
struct HandOver {
  std::string console;  // consoleName() of the one asking
};

using CommandBody = std::variant<LegMove, BodyMove, Grasp, AcquireScan, Hold, GroundHeartbeat,
                                 Resume, RequestAuthority, HandOver>;

using Hmac = std::array<std::uint8_t, 32>;

// A command with its provenance: which console's operator sent it, in
// which order, until when it may be carried out, signed over everything
// else (Signing.h). Times are UTC seconds: ground and rover share a clock.
struct Command {
  std::uint32_t rover_id = 0;
  std::string operator_id;
  std::uint64_t console_id = 0;  // random per console session
  std::uint64_t sequence = 0;
  double time_s = 0.0;         // when signed
  double valid_until_s = 0.0;  // refused on board after this; 0: no window
  CommandBody body;
  std::optional<Hmac> hmac;  // none: unsigned
};

// "alice@00c0ffee3f09a1c2": an operator at one console, as acks, heartbeats and
// logs name it.
std::string consoleName(const std::string& operator_id, std::uint64_t console_id);

// Commands that need command authority: everything but Hold (any
// authenticated console may stop the rover), the console heartbeat and the
// authority exchange itself.
bool needsAuthority(const CommandBody& body);

// Names as they appear in logs and summaries: "LegMove", "Heartbeat", ...
std::string typeName(const TelemetryBody& body);
std::string typeName(const CommandBody& body);

}  // namespace ambler::link
