#include "link/dds/DdsMessages.h"

#include <thread>

#include <algorithm>
#include <cstring>

#include "AmblerLink.h"
#include "link/Codec.h"
#include "link/Link.h"

namespace ambler::link::dds {

namespace {

constexpr std::uint32_t kMaxTake = 64;

// What arrives over DDS passes the codec's checks (finite numbers, legs in
// range, sizes that agree): one set of rules for every way in.
Telemetry checked(const Telemetry& t) { return decodeTelemetry(encode(t)); }
Command checked(const Command& c) { return decodeCommand(encode(c)); }

char* text(const std::string& s) { return const_cast<char*>(s.c_str()); }

template <typename Seq, typename T>
Seq borrowed(const std::vector<T>& v) {
  Seq s{};
  s._maximum = s._length = std::uint32_t(v.size());
  s._buffer = const_cast<T*>(v.data());
  s._release = false;
  return s;
}

ambler_dds_Joints toDds(const gait::LegJoints& q) {
  return {q.rotation_rad, q.extension_m, q.vertical_m};
}
gait::LegJoints fromDds(const ambler_dds_Joints& q) {
  return {q.rotation_rad, q.extension_m, q.vertical_m};
}

void write(dds_entity_t writer, const void* sample) { check(dds_write(writer, sample), "writing"); }

// ---- commands ----

void fillBody(const CommandBody& body, ambler_dds_CommandBody& out,
              std::vector<ambler_dds_Joints>& joints) {
  if (const auto* m = std::get_if<LegMove>(&body)) {
    out._d = ambler_dds_KIND_LEG_MOVE;
    for (const auto& q : m->waypoints) joints.push_back(toDds(q));
    out._u.leg_move.leg = std::uint8_t(m->leg);
    out._u.leg_move.waypoints = borrowed<dds_sequence_ambler_dds_Joints>(joints);
  } else if (const auto* m = std::get_if<BodyMove>(&body)) {
    out._d = ambler_dds_KIND_BODY_MOVE;
    out._u.body_move = {m->x_m, m->y_m, m->rotation_rad, m->raise_m};
  } else if (const auto* m = std::get_if<Grasp>(&body)) {
    out._d = ambler_dds_KIND_GRASP;
    out._u.grasp = {m->x_m, m->y_m, m->z_m, m->yaw_rad, m->opening_m};
  } else if (const auto* m = std::get_if<AcquireScan>(&body)) {
    out._d = ambler_dds_KIND_ACQUIRE_SCAN;
    out._u.acquire_scan = std::uint8_t(m->sensor);
  } else if (std::holds_alternative<Hold>(body)) {
    out._d = ambler_dds_KIND_HOLD;
  } else if (std::holds_alternative<GroundHeartbeat>(body)) {
    out._d = ambler_dds_KIND_GROUND_HEARTBEAT;
  } else if (std::holds_alternative<Resume>(body)) {
    out._d = ambler_dds_KIND_RESUME;
  } else if (std::holds_alternative<RequestAuthority>(body)) {
    out._d = ambler_dds_KIND_REQUEST_AUTHORITY;
  } else {
    out._d = ambler_dds_KIND_HAND_OVER;
    out._u.hand_over = text(std::get<HandOver>(body).console);
  }
}

CommandBody bodyFrom(const ambler_dds_CommandBody& b) {
  switch (b._d) {
    case ambler_dds_KIND_LEG_MOVE: {
      LegMove m{b._u.leg_move.leg, {}};
      for (std::uint32_t i = 0; i < b._u.leg_move.waypoints._length; ++i)
        m.waypoints.push_back(fromDds(b._u.leg_move.waypoints._buffer[i]));
      return m;
    }
    case ambler_dds_KIND_BODY_MOVE: {
      const auto& m = b._u.body_move;
      return BodyMove{m.x_m, m.y_m, m.rotation_rad, m.raise_m};
    }
    case ambler_dds_KIND_GRASP: {
      const auto& m = b._u.grasp;
      return Grasp{m.x_m, m.y_m, m.z_m, m.yaw_rad, m.opening_m};
    }
    case ambler_dds_KIND_ACQUIRE_SCAN:
      if (b._u.acquire_scan > 1)
        throw DecodeError("scan sensor " + std::to_string(b._u.acquire_scan) +
                          " (0 range scanner, 1 light-striper)");
      return AcquireScan{ScanSensor(b._u.acquire_scan)};
    case ambler_dds_KIND_HOLD:
      return Hold{};
    case ambler_dds_KIND_GROUND_HEARTBEAT:
      return GroundHeartbeat{};
    case ambler_dds_KIND_RESUME:
      return Resume{};
    case ambler_dds_KIND_REQUEST_AUTHORITY:
      return RequestAuthority{};
    case ambler_dds_KIND_HAND_OVER:
      return HandOver{b._u.hand_over ? b._u.hand_over : ""};
  }
  throw DecodeError("unknown command kind " + std::to_string(int(b._d)));
}

// Everything but the body, which may not be readable.
Command headerOf(const ambler_dds_Command& s) {
  Command c;
  c.rover_id = s.rover_id;
  c.operator_id = s.operator_id ? s.operator_id : "";
  c.console_id = s.console_id;
  c.sequence = s.sequence_number;
  c.time_s = s.time_s;
  c.valid_until_s = s.valid_until_s;
  if (s.is_signed) {
    c.hmac.emplace();
    std::copy(std::begin(s.hmac), std::end(s.hmac), c.hmac->begin());
  }
  return c;
}

// ---- telemetry ----

class TelemetryWriter {
 public:
  TelemetryWriter(const Entity& heartbeat, const Entity& leg, const Entity& body, const Entity& ack,
                  const Entity& image, const Entity& striper)
      : heartbeat_(heartbeat),
        leg_(leg),
        body_(body),
        ack_(ack),
        image_(image),
        striper_(striper) {}
  void operator()(const Telemetry& t, const Heartbeat& m) const {
    const ambler_dds_Heartbeat s{t.rover_id,
                                 t.time_s,
                                 m.count,
                                 m.holding,
                                 text(m.hold_reason),
                                 text(m.authority),
                                 text(m.authority_request)};
    write(heartbeat_.get(), &s);
  }
  void operator()(const Telemetry& t, const LegState& m) const {
    const ambler_dds_LegState s{t.rover_id,      std::uint8_t(m.leg), t.time_s,
                                toDds(m.joints), m.contact,           m.force_n};
    write(leg_.get(), &s);
  }
  void operator()(const Telemetry& t, const BodyState& m) const {
    const ambler_dds_BodyState s{t.rover_id, t.time_s,      m.x_m,   m.y_m,
                                 m.z_m,      m.heading_rad, m.moving};
    write(body_.get(), &s);
  }
  void operator()(const Telemetry& t, const CommandAck& m) const {
    const ambler_dds_CommandAck s{t.rover_id, t.time_s,   text(m.operator_id), m.console_id,
                                  m.sequence, m.accepted, text(m.reason)};
    write(ack_.get(), &s);
  }
  void operator()(const Telemetry& t, const sensor::RangeImage& m) const {
    ambler_dds_RangeImage s{};
    s.rover_id = t.rover_id, s.time_s = t.time_s;
    s.rows = std::uint32_t(m.rows()), s.cols = std::uint32_t(m.cols());
    s.phi_first = m.geometry.phi_first, s.phi_step = m.geometry.phi_step;
    s.theta_first = m.geometry.theta_first, s.theta_step = m.geometry.theta_step;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) s.sensor_to_world[r * 4 + c] = m.sensor_to_world.matrix()(r, c);
    s.range_sigma_k = m.range_sigma_k;
    s.range = borrowed<dds_sequence_float>(m.range);
    s.reflectance = borrowed<dds_sequence_float>(m.reflectance);
    write(image_.get(), &s);
  }
  void operator()(const Telemetry& t, const sensor::StriperImage& m) const {
    ambler_dds_StriperImage s{};
    s.rover_id = t.rover_id, s.time_s = t.time_s;
    const auto& k = m.camera;
    s.rows = std::uint32_t(k.rows), s.cols = std::uint32_t(k.cols);
    s.fx = k.fx, s.fy = k.fy, s.cx = k.cx, s.cy = k.cy;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) s.camera_to_world[r * 4 + c] = k.camera_to_world.matrix()(r, c);
    for (int i = 0; i < 3; ++i) s.projector_position[i] = m.projector_position[i];
    s.x = borrowed<dds_sequence_float>(m.x);
    s.y = borrowed<dds_sequence_float>(m.y);
    s.z = borrowed<dds_sequence_float>(m.z);
    s.intensity = borrowed<dds_sequence_float>(m.intensity);
    write(striper_.get(), &s);
  }

 private:
  const Entity &heartbeat_, &leg_, &body_, &ack_, &image_, &striper_;
};

Telemetry from(const ambler_dds_Heartbeat& s) {
  return {s.rover_id, s.time_s,
          Heartbeat{s.count, s.holding, s.hold_reason ? s.hold_reason : std::string(),
                    s.authority ? s.authority : std::string(),
                    s.authority_request ? s.authority_request : std::string()}};
}
Telemetry from(const ambler_dds_LegState& s) {
  return {s.rover_id, s.time_s, LegState{s.leg, fromDds(s.joints), s.contact, s.force_n}};
}
Telemetry from(const ambler_dds_BodyState& s) {
  return {s.rover_id, s.time_s, BodyState{s.x_m, s.y_m, s.z_m, s.heading_rad, s.moving}};
}
Telemetry from(const ambler_dds_CommandAck& s) {
  return {s.rover_id, s.time_s,
          CommandAck{s.operator_id ? s.operator_id : "", s.console_id, s.sequence_number,
                     s.accepted, s.reason ? s.reason : ""}};
}
Telemetry from(const ambler_dds_RangeImage& s) {
  sensor::RangeImage m;
  m.geometry = {int(s.rows), int(s.cols), s.phi_first, s.phi_step, s.theta_first, s.theta_step};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m.sensor_to_world.matrix()(r, c) = s.sensor_to_world[r * 4 + c];
  m.range_sigma_k = s.range_sigma_k;
  m.range.assign(s.range._buffer, s.range._buffer + s.range._length);
  m.reflectance.assign(s.reflectance._buffer, s.reflectance._buffer + s.reflectance._length);
  return {s.rover_id, s.time_s, std::move(m)};
}
Telemetry from(const ambler_dds_StriperImage& s) {
  sensor::StriperImage m;
  auto& k = m.camera;
  k.rows = int(s.rows), k.cols = int(s.cols);
  k.fx = s.fx, k.fy = s.fy, k.cx = s.cx, k.cy = s.cy;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) k.camera_to_world.matrix()(r, c) = s.camera_to_world[r * 4 + c];
  for (int i = 0; i < 3; ++i) m.projector_position[i] = s.projector_position[i];
  m.x.assign(s.x._buffer, s.x._buffer + s.x._length);
  m.y.assign(s.y._buffer, s.y._buffer + s.y._length);
  m.z.assign(s.z._buffer, s.z._buffer + s.z._length);
  m.intensity.assign(s.intensity._buffer, s.intensity._buffer + s.intensity._length);
  return {s.rover_id, s.time_s, std::move(m)};
}

}  // namespace

DataWait::DataWait(dds_entity_t participant)
    : waitset_(dds_create_waitset(participant), "creating a DDS waitset") {}

void DataWait::attach(dds_entity_t reader) {
  check(dds_set_status_mask(reader, DDS_DATA_AVAILABLE_STATUS), "setting a reader's status mask");
  check(dds_waitset_attach(waitset_.get(), reader, reader), "attaching a reader");
}

void DataWait::wait(std::chrono::milliseconds timeout) const {
  check(dds_waitset_wait(waitset_.get(), nullptr, 0, DDS_MSECS(timeout.count())),
        "waiting for DDS data");
}

RoverEndpoint::RoverEndpoint(std::uint32_t domain, std::uint32_t rover_id)
    : rover_id_(rover_id),
      participant_(joinDomain(domain)),
      topics_(participant_.get()),
      heartbeat_(makeWriter(participant_.get(), topics_.heartbeat.get(), Traffic::kState)),
      leg_state_(makeWriter(participant_.get(), topics_.leg_state.get(), Traffic::kState)),
      body_state_(makeWriter(participant_.get(), topics_.body_state.get(), Traffic::kState)),
      command_ack_(makeWriter(participant_.get(), topics_.command_ack.get(), Traffic::kAnswers)),
      range_image_(makeWriter(participant_.get(), topics_.range_image.get(), Traffic::kImages)),
      striper_image_(makeWriter(participant_.get(), topics_.striper_image.get(), Traffic::kImages)),
      commands_(makeReader(participant_.get(), topics_.command.get(), Traffic::kCommands)),
      wait_(participant_.get()) {
  wait_.attach(commands_.get());
}

void RoverEndpoint::publish(const Telemetry& message) {
  const TelemetryWriter writer(heartbeat_, leg_state_, body_state_, command_ack_, range_image_,
                               striper_image_);
  std::visit([&](const auto& body) { writer(message, body); }, message.body);
}

std::vector<RoverEndpoint::Received> RoverEndpoint::takeCommands(
    std::chrono::milliseconds timeout) {
  wait_.wait(timeout);
  void* samples[kMaxTake] = {};
  dds_sample_info_t infos[kMaxTake];
  const int n =
      check(dds_take(commands_.get(), samples, infos, kMaxTake, kMaxTake), "taking commands");
  std::vector<Received> out;
  for (int i = 0; i < n; ++i) {
    const auto& s = *static_cast<const ambler_dds_Command*>(samples[i]);
    if (!infos[i].valid_data || s.rover_id != rover_id_) continue;
    Received r{headerOf(s), {}};
    try {
      r.command.body = bodyFrom(s.body);
      r.command = checked(r.command);
    } catch (const DecodeError& e) {
      r.malformed = e.what();
    }
    out.push_back(std::move(r));
  }
  dds_return_loan(commands_.get(), samples, n);
  return out;
}

DdsLink::DdsLink(std::uint32_t domain, std::uint32_t rover_id,
                 std::chrono::milliseconds discovery_wait)
    : domain_(domain),
      rover_id_(rover_id),
      discovery_wait_(discovery_wait),
      participant_(joinDomain(domain)),
      topics_(participant_.get()),
      heartbeat_(makeReader(participant_.get(), topics_.heartbeat.get(), Traffic::kState)),
      leg_state_(makeReader(participant_.get(), topics_.leg_state.get(), Traffic::kState)),
      body_state_(makeReader(participant_.get(), topics_.body_state.get(), Traffic::kState)),
      command_ack_(makeReader(participant_.get(), topics_.command_ack.get(), Traffic::kAnswers)),
      range_image_(makeReader(participant_.get(), topics_.range_image.get(), Traffic::kImages)),
      striper_image_(makeReader(participant_.get(), topics_.striper_image.get(), Traffic::kImages)),
      commands_(makeWriter(participant_.get(), topics_.command.get(), Traffic::kCommands)),
      wait_(participant_.get()) {
  for (const auto* e :
       {&heartbeat_, &leg_state_, &body_state_, &command_ack_, &range_image_, &striper_image_})
    wait_.attach(e->get());
}

// Commands are volatile: one written before discovery has matched the
// rover's reader is lost, so wait for the match (discovery on loopback
// takes tens of milliseconds).
void DdsLink::waitForRover() const {
  const auto until = std::chrono::steady_clock::now() + discovery_wait_;
  do {
    dds_publication_matched_status_t status{};
    check(dds_get_publication_matched_status(commands_.get(), &status), "reading matches");
    if (status.current_count > 0) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  } while (std::chrono::steady_clock::now() < until);
  throw LinkError("no rover listens for commands on DDS domain " + std::to_string(domain_) +
                  " (waited " + std::to_string(discovery_wait_.count() / 1000.0).substr(0, 4) +
                  " s)");
}

void DdsLink::send(const Command& c) {
  waitForRover();
  ambler_dds_Command s{};
  s.rover_id = c.rover_id;
  s.operator_id = text(c.operator_id);
  s.console_id = c.console_id;
  s.sequence_number = c.sequence;
  s.time_s = c.time_s;
  s.valid_until_s = c.valid_until_s;
  s.is_signed = c.hmac.has_value();
  if (c.hmac) std::copy(c.hmac->begin(), c.hmac->end(), s.hmac);
  std::vector<ambler_dds_Joints> joints;
  fillBody(c.body, s.body, joints);
  write(commands_.get(), &s);
}

template <typename Sample, typename Convert>
void DdsLink::takeFrom(dds_entity_t reader, Convert&& convert, std::vector<Telemetry>& out) {
  void* samples[kMaxTake] = {};
  dds_sample_info_t infos[kMaxTake];
  const int n = check(dds_take(reader, samples, infos, kMaxTake, kMaxTake), "taking telemetry");
  for (int i = 0; i < n; ++i) {
    const auto& s = *static_cast<const Sample*>(samples[i]);
    if (!infos[i].valid_data || s.rover_id != rover_id_) continue;
    try {
      out.push_back(checked(convert(s)));
    } catch (const DecodeError&) {
      ++dropped_;
    }
  }
  dds_return_loan(reader, samples, n);
}

std::vector<Telemetry> DdsLink::receive(std::chrono::milliseconds timeout) {
  wait_.wait(timeout);
  std::vector<Telemetry> out;
  auto convert = [](const auto& s) { return from(s); };
  takeFrom<ambler_dds_Heartbeat>(heartbeat_.get(), convert, out);
  takeFrom<ambler_dds_LegState>(leg_state_.get(), convert, out);
  takeFrom<ambler_dds_BodyState>(body_state_.get(), convert, out);
  takeFrom<ambler_dds_CommandAck>(command_ack_.get(), convert, out);
  takeFrom<ambler_dds_RangeImage>(range_image_.get(), convert, out);
  takeFrom<ambler_dds_StriperImage>(striper_image_.get(), convert, out);
  std::stable_sort(out.begin(), out.end(),
                   [](const Telemetry& a, const Telemetry& b) { return a.time_s < b.time_s; });
  return out;
}

std::string DdsLink::describe() const {
  return "DDS domain " + std::to_string(domain_) + ", rover " + std::to_string(rover_id_);
}

}  // namespace ambler::link::dds
