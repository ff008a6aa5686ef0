#pragma once

// Every proposed move waits here for the operator: approve, edit the
// foothold, or reject. An explicit auto-approve mode releases
// proposals without a person, but only those whose interlocks pass; a
// proposal that fails them is never released, whoever approves it. Every
// decision goes to the mission log with who, when and what.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "core/Refusal.h"
#include "executive/Interlocks.h"
#include "missionlog/MissionLog.h"

namespace ambler::executive {

struct StepProposal {
  std::uint64_t id = 0;
  gait::Stance from;
  gait::StepPlan plan;
  std::vector<link::CommandBody> commands;
  InterlockReport interlocks;
  // The recovering leg's sole along its planned path, in the world (for
  // display; empty for a body move).
  std::vector<Eigen::Vector3d> foot_path;
  // What the body does, from `from` to the plan's end: how far its centre
  // moves [m] and how far it turns [deg, positive left]. The plan's body_u
  // is metres or radians, as the walk's heading has it.
  double body_move_m = 0.0;
  double body_turn_deg = 0.0;
};

// The proposal for `plan` from `from`: its commands and their interlocks.
StepProposal makeProposal(std::uint64_t id, const gait::Stance& from, gait::StepPlan plan,
                          const terrain::ElevationMap& map, const gait::GaitContext& context);

// What the log keeps of a proposal: leg, foothold, body move, least
// margin and the interlocks' verdict, as JSON.
std::string describe(const StepProposal& proposal);

// The proposal as the log keeps it for a replay's Step approval dock:
// id, leg, foothold, body advance, least margin and every interlock with
// its figures, as JSON.
std::string proposalRecord(const StepProposal& proposal);
// A logged proposal back, as far as the log keeps it (no stance, paths or
// commands); std::invalid_argument naming what is missing or wrong.
StepProposal proposalFromRecord(const std::string& json);

enum class ApprovalMode { kOperator, kAutoApprove };

inline const std::string kAutoApprover = "auto-approve";

class ApprovalGate {
 public:
  using DecisionSink = std::function<void(const missionlog::Decision&)>;
  explicit ApprovalGate(DecisionSink sink = {}) : sink_(std::move(sink)) {}

  void setMode(ApprovalMode mode) { mode_ = mode; }
  ApprovalMode mode() const { return mode_; }

  // Replaces any pending proposal (a replan supersedes the old one). In
  // auto-approve mode one that passes its interlocks is released at once.
  void propose(StepProposal proposal, double now_s);
  const std::optional<StepProposal>& pending() const { return pending_; }

  // Each is refused when nothing is pending with that id, or (approve)
  // when the interlocks fail.
  Refusal approve(std::uint64_t id, const std::string& operator_id, double now_s);
  Refusal reject(std::uint64_t id, const std::string& operator_id, double now_s,
                 const std::string& reason);
  // The operator moved the foothold; `edited` is the step replanned with
  // it, interlocks checked again. It stays pending until approved.
  Refusal edit(std::uint64_t id, const std::string& operator_id, double now_s, StepProposal edited);

  // The step was suspended: what is pending or approved but not yet sent
  // was planned for a state that no longer holds.
  void withdraw() { pending_.reset(), released_.reset(); }

  // The approved proposal, once, for sending.
  std::optional<StepProposal> takeReleased();

 private:
  Refusal checkPending(std::uint64_t id) const;
  void release(const std::string& operator_id, double now_s);  // the pending step, approved
  void decide(missionlog::Verdict verdict, const std::string& operator_id, double now_s,
              std::uint64_t id, const std::string& detail);

  DecisionSink sink_;
  ApprovalMode mode_ = ApprovalMode::kOperator;
  std::optional<StepProposal> pending_, released_;
};

}  // namespace ambler::executive
