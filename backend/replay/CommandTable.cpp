#include "replay/CommandTable.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <vector>

#include "core/Format.h"

namespace ambler::replay {

std::string describeCommand(const link::CommandBody& body) {
  std::ostringstream s;
  s.precision(3);
  s << link::typeName(body);
  if (const auto* m = std::get_if<link::LegMove>(&body)) {
    s << " leg " << m->leg << ", " << m->waypoints.size() << " waypoints";
  } else if (const auto* b = std::get_if<link::BodyMove>(&body)) {
    s << std::fixed << " (" << b->x_m << ", " << b->y_m << ") m, " << b->rotation_rad * 180.0 / M_PI
      << " deg";
  } else if (const auto* g = std::get_if<link::Grasp>(&body)) {
    s << std::fixed << " at (" << g->x_m << ", " << g->y_m << ", " << g->z_m << ") m";
  } else if (const auto* a = std::get_if<link::AcquireScan>(&body)) {
    s << (a->sensor == link::ScanSensor::kLightStriper ? " light-striper" : " range scanner");
  }
  return s.str();
}

void CommandTable::sent(double time_s, const link::Command& c) {
  const Key key{c.operator_id, c.console_id, c.sequence};
  if (std::holds_alternative<link::GroundHeartbeat>(c.body)) {
    heartbeats_[key] = {time_s, describeCommand(c.body)};
    return;
  }
  open_[key] = rows_.size();
  rows_.push_back({time_s, c.operator_id, describeCommand(c.body), "no answer", ""});
}

void CommandTable::received(double time_s, const link::Telemetry& message) {
  if (const auto* a = std::get_if<link::CommandAck>(&message.body)) {
    answer(time_s, *a);
  } else if (const auto* h = std::get_if<link::Heartbeat>(&message.body)) {
    if (h->holding != holding_) {
      holding_ = h->holding;
      rows_.push_back(
          {time_s, "rover", h->holding ? "holds" : "holds no longer", "", h->hold_reason});
    }
    if (h->authority != authority_ || h->authority_request != authority_request_) {
      authority_ = h->authority, authority_request_ = h->authority_request;
      rows_.push_back({time_s, "rover", "command authority",
                       authority_.empty() ? "none" : authority_,
                       authority_request_.empty() ? "" : authority_request_ + " asks for it"});
    }
  }
}

void CommandTable::answer(double time_s, const link::CommandAck& a) {
  const Key key{a.operator_id, a.console_id, a.sequence};
  const std::string outcome = a.accepted ? "accepted" : "refused";
  if (auto it = open_.find(key); it != open_.end()) {
    rows_[it->second].outcome = outcome, rows_[it->second].reason = a.reason;
    open_.erase(it);
  } else if (auto h = heartbeats_.find(key); h != heartbeats_.end()) {
    if (!a.accepted)
      rows_.push_back({h->second.first, a.operator_id, h->second.second, outcome, a.reason});
  } else {
    // Another console's command, or one sent before this console came.
    rows_.push_back({time_s, "rover",
                     "answer to command " + std::to_string(a.sequence) + " of " +
                         link::consoleName(a.operator_id, a.console_id),
                     outcome, a.reason});
  }
}

void CommandTable::decided(const missionlog::Decision& d) {
  const auto verdict = missionlog::verdictName(d.verdict);
  // A grasp is decided outside the walk's proposals (WalkSession::sendGrasp).
  const bool grasp = d.detail.rfind("{\"grasp\"", 0) == 0;
  rows_.push_back({d.time_s, d.operator_id,
                   verdict + (grasp ? " grasp" : " proposal " + std::to_string(d.proposal)),
                   verdict, describeDecision(d.detail)});
}

void CommandTable::noted(double time_s, const std::string& what) {
  rows_.push_back({time_s, "ground", what, "", ""});
}

namespace {

// "(1.20, 3.40, -0.05) m" from a JSON array, or from a "1.2,3.4,-0.05" string.
std::string triple(const nlohmann::json& j) {
  std::vector<double> v;
  if (j.is_array()) {
    for (const auto& x : j)
      if (x.is_number()) v.push_back(x.get<double>());
  } else if (j.is_string()) {
    std::istringstream in(j.get<std::string>());
    for (std::string part; std::getline(in, part, ',');) {
      try {
        v.push_back(std::stod(part));
      } catch (const std::exception&) {
        return j.get<std::string>();
      }
    }
  }
  if (v.size() != 3) return j.dump();
  return "(" + fixed(v[0], 2) + ", " + fixed(v[1], 2) + ", " + fixed(v[2], 2) + ") m";
}

std::string describeGrasp(const nlohmann::json& fit) {
  std::vector<std::string> parts;
  if (fit.contains("centre_m")) parts.push_back("rock at " + triple(fit["centre_m"]));
  if (fit.contains("size_m")) parts.push_back("size " + triple(fit["size_m"]));
  if (fit.contains("rms_m") && fit["rms_m"].is_number())
    parts.push_back("fit rms " + fixed(fit["rms_m"].get<double>() * 1000.0, 1) + " mm");
  if (fit.contains("points") && fit["points"].is_number())
    parts.push_back(std::to_string(fit["points"].get<long>()) + " points");
  std::string out;
  for (const auto& p : parts) out += (out.empty() ? "" : ", ") + p;
  return out;
}

}  // namespace

std::string describeDecision(const std::string& detail) {
  const auto j = nlohmann::json::parse(detail, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return detail;
  if (j.contains("grasp") && j["grasp"].is_object()) return describeGrasp(j["grasp"]);
  std::vector<std::string> parts;
  const auto number = [&](const char* key) {
    return j.contains(key) && j[key].is_number() ? std::optional(j[key].get<double>())
                                                 : std::nullopt;
  };
  if (const auto leg = number("leg"); leg && *leg >= 0)
    parts.push_back("leg " + std::to_string(int(*leg)) +
                    (j.contains("foothold_m") ? " to " + triple(j["foothold_m"]) : ""));
  else if (leg)
    parts.push_back("body move only");
  if (const auto m = number("body_move_m"))
    parts.push_back("body moves " + fixed(*m, 2) + " m, turns " +
                    fixed(number("body_turn_deg").value_or(0.0), 1) + " deg");
  else if (const auto u = number("body_advance"))  // a log from before the two above
    parts.push_back("body advance " + fixed(*u, 2) + " m");
  if (const auto m = number("min_csp_margin_m"))
    parts.push_back("least stability margin " + fixed(*m, 2) + " m");
  if (j.contains("interlocks") && j["interlocks"].is_string()) {
    const auto interlocks = j["interlocks"].get<std::string>();
    parts.push_back(interlocks == "passed" ? "interlocks passed"
                                           : "interlock failed: " + interlocks);
  }
  std::string out;
  for (const auto& p : parts) out += (out.empty() ? "" : ", ") + p;
  if (j.contains("reason") && j["reason"].is_string())
    out += (out.empty() ? "" : "; ") + ("reason: " + j["reason"].get<std::string>());
  return out.empty() ? detail : out;
}

}  // namespace ambler::replay
