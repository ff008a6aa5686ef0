#include "gait/RoverConfig.h"

#include <initializer_list>
#include <stdexcept>
#include <utility>

#include "core/Resources.h"
#include "footfall/FootfallConfig.h"
#include "io/Json.h"

namespace ambler::gait {

namespace {

void readPair(const io::JsonFields& f, const char* key, double* lo, double* hi) {
  if (!f.has(key)) return;
  const auto v = f.numbers(key, 2);
  *lo = v[0];
  *hi = v[1];
}

void readVector(const io::JsonFields& f, const char* key, Eigen::Vector2d* out) {
  if (!f.has(key)) return;
  const auto v = f.numbers(key, 2);
  *out = {v[0], v[1]};
}

void readRover(const io::JsonFields& f, RoverModel& m) {
  if (f.has("shafts_m")) {
    const auto v = f.numbers("shafts_m", 4);
    m.shafts = {Eigen::Vector2d(v[0], v[1]), Eigen::Vector2d(v[2], v[3])};
  }
  readPair(f, "extension_m", &m.extension_min_m, &m.extension_max_m);
  readPair(f, "vertical_m", &m.vertical_min_m, &m.vertical_max_m);
  readVector(f, "centre_of_gravity_m", &m.centre_of_gravity);
  readVector(f, "body_keepout_half_m", &m.body_keepout_half);
  const struct {
    const char* section;
    const char* key;
    double* value;
  } numbers[] = {
      {nullptr, "foot_diameter_m", &m.foot_diameter_m},
      {nullptr, "link_plane_nominal_m", &m.link_plane_nominal_m},
      {nullptr, "mass_kg", &m.mass_kg},
      {nullptr, "shaft_clearance_m", &m.shaft_clearance_m},
      {nullptr, "min_leg_separation_m", &m.min_leg_separation_m},
      {"speeds", "rotation_rad_s", &m.rotation_speed_rad_s},
      {"speeds", "extension_m_s", &m.extension_speed_m_s},
      {"speeds", "vertical_m_s", &m.vertical_speed_m_s},
      {"speeds", "body_m_s", &m.body_speed_m_s},
      {"speeds", "body_turn_rad_s", &m.body_turn_speed_rad_s},
      {"speeds", "body_accel_m_s2", &m.body_accel_m_s2},
      {"power_w", "recovery", &m.recovery_power_w},
      {"power_w", "propulsion", &m.propulsion_power_w},
  };
  for (const auto& n : numbers) {
    if (!n.section) {
      if (f.has(n.key)) *n.value = f.number(n.key);
      continue;
    }
    if (!f.has(n.section)) continue;
    const auto s = f.object(n.section);
    if (s.has(n.key)) *n.value = s.number(n.key);
  }
}

// The keys of one section that are plain numbers; missing keys keep their value.
using NumberKeys = std::initializer_list<std::pair<const char*, double*>>;
void readNumbers(const io::JsonFields& f, NumberKeys keys) {
  for (const auto& [key, value] : keys)
    if (f.has(key)) *value = f.number(key);
}

void readGait(const io::JsonFields& f, GaitOptions& g) {
  readNumbers(f, {{"tread_m", &g.tread_m},
                  {"pitch_m", &g.pitch_m},
                  {"max_body_advance_m", &g.max_body_advance_m},
                  {"csp_margin_m", &g.csp_margin_m},
                  {"execution_slack_m", &g.execution_slack_m},
                  {"search_half_m", &g.search_half_m},
                  {"tread_tolerance_m", &g.tread_tolerance_m},
                  {"pattern_weight", &g.pattern_weight},
                  {"max_stack_span_pitches", &g.max_stack_span_pitches},
                  {"max_stack_lead_pitches", &g.max_stack_lead_pitches},
                  {"body_step_m", &g.body_step_m}});
  if (f.has("max_body_turn_deg")) g.max_body_turn_rad = f.number("max_body_turn_deg") * M_PI / 180;
  if (f.has("max_candidates_per_leg"))
    g.max_candidates_per_leg = f.integer("max_candidates_per_leg");
}

void readRecovery(const io::JsonFields& f, RecoveryOptions& r) {
  readNumbers(f, {{"rotation_step_rad", &r.rotation_step_rad},
                  {"extension_step_m", &r.extension_step_m},
                  {"clearance_m", &r.clearance_m},
                  {"uncertainty_m", &r.uncertainty_m},
                  {"power_time_ratio", &r.power_time_ratio},
                  {"leg_mass_kg", &r.leg_mass_kg}});
}

void validate(const RecoveryOptions& r) {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(what);
  };
  require(r.rotation_step_rad >= 0.01 && r.rotation_step_rad <= 0.5,
          "recovery.rotation_step_rad must be in [0.01, 0.5]");
  require(r.extension_step_m >= 0.01 && r.extension_step_m <= 0.5,
          "recovery.extension_step_m must be in [0.01, 0.5]");
  require(r.clearance_m >= 0 && r.clearance_m <= 2, "recovery.clearance_m must be in [0, 2]");
  require(r.uncertainty_m >= 0 && r.uncertainty_m <= 2, "recovery.uncertainty_m must be in [0, 2]");
  require(r.power_time_ratio >= 0 && r.power_time_ratio <= 1000,
          "recovery.power_time_ratio must be in [0, 1000]");
  require(r.leg_mass_kg > 0, "recovery.leg_mass_kg must be > 0");
}

}  // namespace

GaitContext readRoverConfig(const std::filesystem::path& path) {
  const auto json = io::readJsonFile(path);
  const std::string context = "rover configuration '" + path.string() + "'";
  const io::JsonFields root(json, context);
  GaitContext ctx;
  if (root.has("rover")) readRover(root.object("rover"), ctx.model);
  if (root.has("gait")) readGait(root.object("gait"), ctx.gait);
  if (root.has("recovery")) readRecovery(root.object("recovery"), ctx.recovery);
  try {
    validate(ctx.model);
    validate(ctx.gait);
    validate(ctx.recovery);
  } catch (const std::invalid_argument& e) {
    throw io::FormatError(context + ": " + e.what());
  }
  return ctx;
}

GaitContext readGaitContext(const std::filesystem::path& rover_json,
                            const std::filesystem::path& footfall_json) {
  GaitContext ctx = readRoverConfig(rover_json);
  ctx.footfall = footfall::readFootfallConfig(footfall_json);
  return ctx;
}

GaitContext readInstalledGaitContext() {
  return readGaitContext(findResource("config/rover.json"), findResource("config/footfall.json"));
}

}  // namespace ambler::gait
