#include "executive/ApprovalGate.h"

#include "gait/LegRecovery.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace ambler::executive {

StepProposal makeProposal(std::uint64_t id, const gait::Stance& from, gait::StepPlan plan,
                          const terrain::ElevationMap& map, const gait::GaitContext& context) {
  StepProposal p;
  p.id = id;
  p.from = from;
  p.plan = std::move(plan);
  p.commands = stepCommands(p.plan, from);
  p.interlocks = checkInterlocks(p.plan, from, p.commands, map, context);
  if (p.plan.leg >= 0 && p.plan.recovery.found)
    p.foot_path = gait::footPath(context.model, from, p.plan.leg, p.plan.recovery, p.plan.foothold);
  p.body_move_m = (p.plan.after.body.xy - from.body.xy).norm();
  p.body_turn_deg =
      std::remainder(p.plan.after.body.heading_rad - from.body.heading_rad, 2 * M_PI) * 180 / M_PI;
  return p;
}

std::string describe(const StepProposal& p) {
  nlohmann::json j = {
      {"proposal", p.id},
      {"leg", p.plan.leg},
      {"body_advance", p.plan.body_u},
      {"body_move_m", p.body_move_m},
      {"body_turn_deg", p.body_turn_deg},
      {"min_csp_margin_m", p.plan.min_csp_margin},
      {"interlocks", p.interlocks.passed() ? "passed" : p.interlocks.firstFailure()}};
  if (p.plan.leg >= 0)
    j["foothold_m"] = {p.plan.foothold.x(), p.plan.foothold.y(), p.plan.foothold.z()};
  return j.dump();
}

std::string proposalRecord(const StepProposal& p) {
  nlohmann::json checks = nlohmann::json::array();
  for (const auto& c : p.interlocks.checks)
    checks.push_back({{"name", c.name}, {"passed", c.passed}, {"detail", c.detail}});
  return nlohmann::json{
      {"proposal", p.id},
      {"leg", p.plan.leg},
      {"foothold_m", {p.plan.foothold.x(), p.plan.foothold.y(), p.plan.foothold.z()}},
      {"body_advance", p.plan.body_u},
      {"body_move_m", p.body_move_m},
      {"body_turn_deg", p.body_turn_deg},
      {"min_csp_margin_m", p.plan.min_csp_margin},
      {"interlocks", checks}}
      .dump();
}

StepProposal proposalFromRecord(const std::string& json) {
  const auto j = nlohmann::json::parse(json, nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw std::invalid_argument("not a JSON object");
  const auto number = [&](const char* key) {
    if (!j.contains(key) || !j[key].is_number())
      throw std::invalid_argument(std::string("no number \"") + key + "\"");
    return j[key].get<double>();
  };
  StepProposal p;
  p.id = std::uint64_t(number("proposal"));
  p.plan.leg = int(number("leg"));
  p.plan.body_u = number("body_advance");
  // Logs from before these two were kept hold straight walks only, whose
  // body_u is the body's move in metres.
  p.body_move_m = j.contains("body_move_m") ? number("body_move_m") : p.plan.body_u;
  p.body_turn_deg = j.contains("body_turn_deg") ? number("body_turn_deg") : 0.0;
  p.plan.min_csp_margin = number("min_csp_margin_m");
  const auto& foot = j.value("foothold_m", nlohmann::json());
  if (!foot.is_array() || foot.size() != 3 || !foot[0].is_number() || !foot[1].is_number() ||
      !foot[2].is_number())
    throw std::invalid_argument("\"foothold_m\" is not three numbers");
  p.plan.foothold = {foot[0].get<double>(), foot[1].get<double>(), foot[2].get<double>()};
  if (!j.contains("interlocks") || !j["interlocks"].is_array())
    throw std::invalid_argument("no \"interlocks\" list");
  for (const auto& c : j["interlocks"]) {
    if (!c.is_object() || !c.contains("name") || !c["name"].is_string() || !c.contains("passed") ||
        !c["passed"].is_boolean())
      throw std::invalid_argument("an interlock without a name and a verdict");
    p.interlocks.checks.push_back(
        {c["name"].get<std::string>(), c["passed"].get<bool>(), c.value("detail", std::string())});
  }
  return p;
}

void ApprovalGate::propose(StepProposal proposal, double now_s) {
  pending_ = std::move(proposal);
  if (mode_ == ApprovalMode::kAutoApprove && pending_->interlocks.passed())
    release(kAutoApprover, now_s);
}

Refusal ApprovalGate::checkPending(std::uint64_t id) const {
  if (!pending_) return Refusal::because("no step is waiting for a decision");
  if (pending_->id != id)
    return Refusal::because("step " + std::to_string(id) + " is not the one waiting (step " +
                            std::to_string(pending_->id) + " is)");
  return {};
}

Refusal ApprovalGate::approve(std::uint64_t id, const std::string& operator_id, double now_s) {
  if (auto problem = checkPending(id); problem.refused()) return problem;
  if (!pending_->interlocks.passed())
    return Refusal::because("interlock failed, the step cannot be sent: " +
                            pending_->interlocks.firstFailure());
  release(operator_id, now_s);
  return {};
}

void ApprovalGate::release(const std::string& operator_id, double now_s) {
  decide(missionlog::Verdict::kApproved, operator_id, now_s, pending_->id, describe(*pending_));
  released_ = std::move(pending_);
  pending_.reset();
}

Refusal ApprovalGate::reject(std::uint64_t id, const std::string& operator_id, double now_s,
                             const std::string& reason) {
  if (auto problem = checkPending(id); problem.refused()) return problem;
  auto detail = nlohmann::json::parse(describe(*pending_));
  detail["reason"] = reason;
  decide(missionlog::Verdict::kRejected, operator_id, now_s, id, detail.dump());
  pending_.reset();
  return {};
}

Refusal ApprovalGate::edit(std::uint64_t id, const std::string& operator_id, double now_s,
                           StepProposal edited) {
  if (auto problem = checkPending(id); problem.refused()) return problem;
  edited.id = id;
  decide(missionlog::Verdict::kEdited, operator_id, now_s, id, describe(edited));
  pending_ = std::move(edited);
  return {};
}

std::optional<StepProposal> ApprovalGate::takeReleased() {
  auto out = std::move(released_);
  released_.reset();
  return out;
}

void ApprovalGate::decide(missionlog::Verdict verdict, const std::string& operator_id, double now_s,
                          std::uint64_t id, const std::string& detail) {
  if (sink_) sink_({now_s, operator_id, id, verdict, detail});
}

}  // namespace ambler::executive
