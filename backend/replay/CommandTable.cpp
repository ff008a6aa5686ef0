#include "replay/CommandTable.h"

#include <cmath>
#include <sstream>

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
  const Key key{c.operator_id, c.sequence};
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
    if (h->holding == holding_) return;
    holding_ = h->holding;
    rows_.push_back(
        {time_s, "rover", h->holding ? "holds" : "holds no longer", "", h->hold_reason});
  }
}

void CommandTable::answer(double time_s, const link::CommandAck& a) {
  const Key key{a.operator_id, a.sequence};
  const std::string outcome = a.accepted ? "accepted" : "refused";
  if (auto it = open_.find(key); it != open_.end()) {
    rows_[it->second].outcome = outcome, rows_[it->second].reason = a.reason;
    open_.erase(it);
  } else if (auto h = heartbeats_.find(key); h != heartbeats_.end()) {
    if (!a.accepted)
      rows_.push_back({h->second.first, a.operator_id, h->second.second, outcome, a.reason});
  } else {
    rows_.push_back({time_s, "rover", "answer to an unknown command " + std::to_string(a.sequence),
                     outcome, a.reason});
  }
}

void CommandTable::decided(const missionlog::Decision& d) {
  const auto verdict = missionlog::verdictName(d.verdict);
  // A grasp is decided outside the walk's proposals (WalkSession::sendGrasp).
  const bool grasp = d.detail.rfind("{\"grasp\"", 0) == 0;
  rows_.push_back({d.time_s, d.operator_id,
                   verdict + (grasp ? " grasp" : " proposal " + std::to_string(d.proposal)),
                   verdict, d.detail});
}

}  // namespace ambler::replay
