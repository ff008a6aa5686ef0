#include "link/Codec.h"

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <type_traits>

namespace ambler::link {

namespace {

constexpr std::uint8_t kMagic[4] = {'A', 'M', 'B', 'L'};
// 2: holding, GroundHeartbeat, Resume, striper; 3: console ids, validity
// windows, command authority. Version 2 is still read (mission logs).
constexpr std::uint8_t kVersion = 3, kOldestReadable = 2;
constexpr std::uint8_t kTelemetryKind = 0, kCommandKind = 1;
constexpr std::size_t kMaxText = 256;        // operator ids, reasons
constexpr std::size_t kMaxWaypoints = 64;    // per leg move
constexpr std::size_t kMaxImageSide = 8192;  // rows or columns of a range image

static_assert(std::endian::native == std::endian::little, "the codec assumes a little-endian host");

class Writer {
 public:
  template <typename T>
  void put(T value) {
    static_assert(std::is_arithmetic_v<T>);
    const auto* p = reinterpret_cast<const std::uint8_t*>(&value);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void put(bool value) { put(std::uint8_t(value ? 1 : 0)); }
  void put(const std::string& text) {
    put(std::uint16_t(text.size()));
    bytes_.insert(bytes_.end(), text.begin(), text.end());
  }
  void putRaw(const std::uint8_t* p, std::size_t n) { bytes_.insert(bytes_.end(), p, p + n); }
  Bytes take() { return std::move(bytes_); }

 private:
  Bytes bytes_;
};

class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  std::uint8_t version = kVersion;  // of the message being read

  template <typename T>
  T get(const char* what) {
    static_assert(std::is_arithmetic_v<T>);
    need(sizeof(T), what);
    T value;
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  bool getBool(const char* what) {
    const auto v = get<std::uint8_t>(what);
    if (v > 1) fail(std::string(what) + " is " + std::to_string(v) + ", not 0 or 1");
    return v == 1;
  }
  double getFinite(const char* what) {
    const double v = get<double>(what);
    if (!std::isfinite(v)) fail(std::string(what) + " is not a finite number");
    return v;
  }
  std::string getText(const char* what) {
    const auto n = get<std::uint16_t>(what);
    if (n > kMaxText)
      fail(std::string(what) + " is " + std::to_string(n) + " bytes, over " +
           std::to_string(kMaxText));
    need(n, what);
    std::string text(reinterpret_cast<const char*>(bytes_.data() + at_), n);
    at_ += n;
    return text;
  }
  void getRaw(std::uint8_t* out, std::size_t n, const char* what) {
    need(n, what);
    std::memcpy(out, bytes_.data() + at_, n);
    at_ += n;
  }
  void expectEnd() const {
    if (at_ != bytes_.size())
      fail(std::to_string(bytes_.size() - at_) + " bytes left over after the message");
  }
  [[noreturn]] void fail(const std::string& problem) const {
    throw DecodeError("message byte " + std::to_string(at_) + ": " + problem);
  }

 private:
  void need(std::size_t n, const char* what) const {
    if (bytes_.size() - at_ < n)
      throw DecodeError("message truncated at byte " + std::to_string(bytes_.size()) +
                        " while reading " + what);
  }
  std::span<const std::uint8_t> bytes_;
  std::size_t at_ = 0;
};

void writeHeader(Writer& w, std::uint8_t kind, std::size_t type) {
  w.putRaw(kMagic, 4);
  w.put(kVersion);
  w.put(kind);
  w.put(std::uint8_t(type));
}

std::size_t readHeader(Reader& r, std::uint8_t kind, std::size_t types) {
  std::uint8_t magic[4];
  r.getRaw(magic, 4, "magic");
  if (std::memcmp(magic, kMagic, 4) != 0) r.fail("not an Ambler message (bad magic)");
  const auto version = r.get<std::uint8_t>("version");
  if (version < kOldestReadable || version > kVersion)
    r.fail("unsupported version " + std::to_string(version));
  r.version = version;
  const auto got_kind = r.get<std::uint8_t>("kind");
  if (got_kind != kind)
    r.fail(std::string("expected a ") + (kind == kCommandKind ? "command" : "telemetry") +
           " message, got kind " + std::to_string(got_kind));
  const auto type = r.get<std::uint8_t>("type");
  if (type >= types) r.fail("unknown message type " + std::to_string(type));
  return type;
}

void putJoints(Writer& w, const gait::LegJoints& j) {
  w.put(j.rotation_rad), w.put(j.extension_m), w.put(j.vertical_m);
}

gait::LegJoints getJoints(Reader& r) {
  gait::LegJoints j;
  j.rotation_rad = r.getFinite("joint rotation");
  j.extension_m = r.getFinite("joint extension");
  j.vertical_m = r.getFinite("joint vertical");
  return j;
}

int getLeg(Reader& r) {
  const auto leg = r.get<std::uint8_t>("leg");
  if (leg >= gait::kLegCount)
    r.fail("leg " + std::to_string(leg) + " out of range 0.." +
           std::to_string(gait::kLegCount - 1));
  return leg;
}

// The top three rows of a rigid pose, row-major.
void putPose(Writer& w, const Eigen::Isometry3d& pose) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) w.put(pose.matrix()(r, c));
}

void getPose(Reader& r, Eigen::Isometry3d& pose, const char* what) {
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 4; ++c) pose.matrix()(i, c) = r.getFinite(what);
}

void putFloats(Writer& w, const std::vector<float>& values) {
  w.putRaw(reinterpret_cast<const std::uint8_t*>(values.data()), values.size() * sizeof(float));
}

// `n` float32 values into `values`.
void getFloats(Reader& r, std::vector<float>& values, std::size_t n, const char* what) {
  values.resize(n);
  r.getRaw(reinterpret_cast<std::uint8_t*>(values.data()), n * sizeof(float), what);
}

// ---- bodies ----

void put(Writer& w, const Heartbeat& m) {
  w.put(m.count), w.put(m.holding), w.put(m.hold_reason);
  w.put(m.authority), w.put(m.authority_request);
}
void put(Writer& w, const LegState& m) {
  w.put(std::uint8_t(m.leg)), putJoints(w, m.joints), w.put(m.contact), w.put(m.force_n);
}
void put(Writer& w, const BodyState& m) {
  w.put(m.x_m), w.put(m.y_m), w.put(m.z_m), w.put(m.heading_rad), w.put(m.moving);
}
void put(Writer& w, const CommandAck& m) {
  w.put(m.operator_id), w.put(m.console_id), w.put(m.sequence), w.put(m.accepted), w.put(m.reason);
}
void put(Writer& w, const sensor::RangeImage& m) {
  const auto& g = m.geometry;
  w.put(std::uint32_t(g.rows)), w.put(std::uint32_t(g.cols));
  w.put(g.phi_first), w.put(g.phi_step), w.put(g.theta_first), w.put(g.theta_step);
  putPose(w, m.sensor_to_world);
  w.put(m.range_sigma_k);
  w.put(!m.reflectance.empty());
  putFloats(w, m.range);
  putFloats(w, m.reflectance);
}
void put(Writer& w, const LegMove& m) {
  w.put(std::uint8_t(m.leg)), w.put(std::uint16_t(m.waypoints.size()));
  for (const auto& j : m.waypoints) putJoints(w, j);
}
void put(Writer& w, const BodyMove& m) {
  w.put(m.x_m), w.put(m.y_m), w.put(m.rotation_rad), w.put(m.raise_m);
}
void put(Writer& w, const Grasp& m) {
  w.put(m.x_m), w.put(m.y_m), w.put(m.z_m), w.put(m.yaw_rad), w.put(m.opening_m);
}
void put(Writer& w, const sensor::StriperImage& m) {
  const auto& k = m.camera;
  w.put(std::uint32_t(k.rows)), w.put(std::uint32_t(k.cols));
  w.put(k.fx), w.put(k.fy), w.put(k.cx), w.put(k.cy);
  putPose(w, k.camera_to_world);
  for (int i = 0; i < 3; ++i) w.put(m.projector_position[i]);
  for (const auto* channel : {&m.x, &m.y, &m.z, &m.intensity}) putFloats(w, *channel);
}
void put(Writer& w, const AcquireScan& m) { w.put(std::uint8_t(m.sensor)); }
void put(Writer&, const Hold&) {}
void put(Writer&, const GroundHeartbeat&) {}
void put(Writer&, const Resume&) {}
void put(Writer&, const RequestAuthority&) {}
void put(Writer& w, const HandOver& m) { w.put(m.console); }

template <typename T>
T get(Reader& r);

template <>
Heartbeat get(Reader& r) {
  Heartbeat m;
  m.count = r.get<std::uint64_t>("heartbeat count");
  m.holding = r.getBool("holding");
  m.hold_reason = r.getText("hold reason");
  if (r.version >= 3) {
    m.authority = r.getText("authority");
    m.authority_request = r.getText("authority request");
  }
  return m;
}
template <>
LegState get(Reader& r) {
  LegState m;
  m.leg = getLeg(r);
  m.joints = getJoints(r);
  m.contact = r.getBool("contact");
  m.force_n = r.getFinite("foot force");
  return m;
}
template <>
BodyState get(Reader& r) {
  BodyState m;
  m.x_m = r.getFinite("body x"), m.y_m = r.getFinite("body y"), m.z_m = r.getFinite("body z");
  m.heading_rad = r.getFinite("body heading");
  m.moving = r.getBool("moving");
  return m;
}
template <>
CommandAck get(Reader& r) {
  CommandAck m;
  m.operator_id = r.getText("ack operator");
  if (r.version >= 3) m.console_id = r.get<std::uint64_t>("ack console");
  m.sequence = r.get<std::uint64_t>("ack sequence");
  m.accepted = r.getBool("ack accepted");
  m.reason = r.getText("ack reason");
  return m;
}
// An image's rows and columns, each 1..kMaxImageSide.
std::pair<std::uint32_t, std::uint32_t> getImageSize(Reader& r, const std::string& kind) {
  const auto rows = r.get<std::uint32_t>("image rows"), cols = r.get<std::uint32_t>("image cols");
  if (rows == 0 || cols == 0 || rows > kMaxImageSide || cols > kMaxImageSide)
    r.fail(kind + " of " + std::to_string(rows) + " x " + std::to_string(cols) + " pixels (1.." +
           std::to_string(kMaxImageSide) + " each way)");
  return {rows, cols};
}

template <>
sensor::RangeImage get(Reader& r) {
  sensor::RangeImage m;
  auto& g = m.geometry;
  const auto [rows, cols] = getImageSize(r, "range image");
  g.rows = int(rows), g.cols = int(cols);
  g.phi_first = r.getFinite("phi_first"), g.phi_step = r.getFinite("phi_step");
  g.theta_first = r.getFinite("theta_first"), g.theta_step = r.getFinite("theta_step");
  getPose(r, m.sensor_to_world, "sensor pose");
  m.range_sigma_k = r.getFinite("range_sigma_k");
  const bool has_reflectance = r.getBool("reflectance flag");
  const std::size_t pixels = std::size_t(rows) * cols;
  getFloats(r, m.range, pixels, "ranges");
  if (has_reflectance) getFloats(r, m.reflectance, pixels, "reflectance");
  if (const auto problem = sensor::findProblem(m); !problem.empty()) r.fail(problem);
  return m;
}
template <>
LegMove get(Reader& r) {
  LegMove m;
  m.leg = getLeg(r);
  const auto n = r.get<std::uint16_t>("waypoint count");
  if (n == 0 || n > kMaxWaypoints)
    r.fail(std::to_string(n) + " waypoints (1.." + std::to_string(kMaxWaypoints) + ")");
  for (int i = 0; i < n; ++i) m.waypoints.push_back(getJoints(r));
  return m;
}
template <>
BodyMove get(Reader& r) {
  BodyMove m;
  m.x_m = r.getFinite("body move x"), m.y_m = r.getFinite("body move y");
  m.rotation_rad = r.getFinite("body move rotation"), m.raise_m = r.getFinite("body move raise");
  return m;
}
template <>
Grasp get(Reader& r) {
  Grasp m;
  m.x_m = r.getFinite("grasp x"), m.y_m = r.getFinite("grasp y"), m.z_m = r.getFinite("grasp z");
  m.yaw_rad = r.getFinite("grasp yaw"), m.opening_m = r.getFinite("grasp opening");
  return m;
}
template <>
sensor::StriperImage get(Reader& r) {
  sensor::StriperImage m;
  auto& k = m.camera;
  const auto [rows, cols] = getImageSize(r, "striper image");
  k.rows = int(rows), k.cols = int(cols);
  k.fx = r.getFinite("fx"), k.fy = r.getFinite("fy");
  k.cx = r.getFinite("cx"), k.cy = r.getFinite("cy");
  getPose(r, k.camera_to_world, "camera pose");
  for (int i = 0; i < 3; ++i) m.projector_position[i] = r.getFinite("projector position");
  const std::size_t pixels = std::size_t(rows) * cols;
  getFloats(r, m.x, pixels, "X");
  getFloats(r, m.y, pixels, "Y");
  getFloats(r, m.z, pixels, "Z");
  getFloats(r, m.intensity, pixels, "intensity");
  if (const auto problem = sensor::findProblem(m); !problem.empty()) r.fail(problem);
  return m;
}
template <>
AcquireScan get(Reader& r) {
  const auto sensor = r.get<std::uint8_t>("scan sensor");
  if (sensor > 1)
    r.fail("scan sensor " + std::to_string(sensor) + " (0 range scanner, 1 light-striper)");
  return {ScanSensor(sensor)};
}
template <>
Hold get(Reader&) {
  return {};
}
template <>
GroundHeartbeat get(Reader&) {
  return {};
}
template <>
Resume get(Reader&) {
  return {};
}
template <>
RequestAuthority get(Reader&) {
  return {};
}
template <>
HandOver get(Reader& r) {
  return {r.getText("hand-over console")};
}

// The variant alternative with index `type`, read from `r`.
template <typename Variant, std::size_t I = 0>
Variant getBody(Reader& r, std::size_t type) {
  if constexpr (I < std::variant_size_v<Variant>) {
    if (type == I) return get<std::variant_alternative_t<I, Variant>>(r);
    return getBody<Variant, I + 1>(r, type);
  } else {
    r.fail("unknown message type " + std::to_string(type));
  }
}

void putCommandContent(Writer& w, const Command& c) {
  writeHeader(w, kCommandKind, c.body.index());
  w.put(c.rover_id), w.put(c.operator_id), w.put(c.console_id), w.put(c.sequence);
  w.put(c.time_s), w.put(c.valid_until_s);
  std::visit([&](const auto& body) { put(w, body); }, c.body);
}

}  // namespace

Bytes encode(const Telemetry& m) {
  Writer w;
  writeHeader(w, kTelemetryKind, m.body.index());
  w.put(m.rover_id), w.put(m.time_s);
  std::visit([&](const auto& body) { put(w, body); }, m.body);
  return w.take();
}

Bytes signedContent(const Command& c) {
  Writer w;
  putCommandContent(w, c);
  return w.take();
}

Bytes encode(const Command& c) {
  Writer w;
  putCommandContent(w, c);
  w.put(c.hmac.has_value());
  if (c.hmac) w.putRaw(c.hmac->data(), c.hmac->size());
  return w.take();
}

Telemetry decodeTelemetry(std::span<const std::uint8_t> bytes) {
  Reader r(bytes);
  const auto type = readHeader(r, kTelemetryKind, std::variant_size_v<TelemetryBody>);
  Telemetry m;
  m.rover_id = r.get<std::uint32_t>("rover id");
  m.time_s = r.getFinite("time");
  m.body = getBody<TelemetryBody>(r, type);
  r.expectEnd();
  return m;
}

Command decodeCommand(std::span<const std::uint8_t> bytes) {
  Reader r(bytes);
  const auto type = readHeader(r, kCommandKind, std::variant_size_v<CommandBody>);
  Command c;
  c.rover_id = r.get<std::uint32_t>("rover id");
  c.operator_id = r.getText("operator id");
  if (r.version >= 3) c.console_id = r.get<std::uint64_t>("console id");
  c.sequence = r.get<std::uint64_t>("sequence");
  c.time_s = r.getFinite("time");
  if (r.version >= 3) c.valid_until_s = r.getFinite("valid until");
  c.body = getBody<CommandBody>(r, type);
  if (r.getBool("signature flag")) {
    c.hmac.emplace();
    r.getRaw(c.hmac->data(), c.hmac->size(), "signature");
  }
  r.expectEnd();
  return c;
}

std::string typeName(const TelemetryBody& body) {
  static const char* names[] = {"Heartbeat",  "LegState",   "BodyState",
                                "CommandAck", "RangeImage", "StriperImage"};
  static_assert(std::size(names) == std::variant_size_v<TelemetryBody>);
  return names[body.index()];
}

std::string typeName(const CommandBody& body) {
  static const char* names[] = {"LegMove", "BodyMove",        "Grasp",  "AcquireScan",
                                "Hold",    "GroundHeartbeat", "Resume", "RequestAuthority",
                                "HandOver"};
  static_assert(std::size(names) == std::variant_size_v<CommandBody>);
  return names[body.index()];
}

std::string consoleName(const std::string& operator_id, std::uint64_t console_id) {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(console_id));
  return operator_id + "@" + hex;
}

bool needsAuthority(const CommandBody& body) {
  return !std::holds_alternative<Hold>(body) && !std::holds_alternative<GroundHeartbeat>(body) &&
         !std::holds_alternative<RequestAuthority>(body) && !std::holds_alternative<HandOver>(body);
}

}  // namespace ambler::link
