#include "executive/WalkExecutive.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

#include "gait/LegRecovery.h"
#include "terrain/Merge.h"

namespace ambler::executive {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string moveName(const MoveUnderWay& move) {
  return move.type + " " + std::to_string(move.sequence);
}

}  // namespace

std::string phaseName(Phase phase) {
  switch (phase) {
    case Phase::kIdle:
      return "idle";
    case Phase::kConnecting:
      return "waiting for the rover";
    case Phase::kScanning:
      return "scanning";
    case Phase::kAwaitingDecision:
      return "awaiting decision";
    case Phase::kExecuting:
      return "executing";
    case Phase::kAwaitingMoveEnd:
      return "waiting for the move under way to end";
    case Phase::kSuspended:
      return "suspended";
    case Phase::kDone:
      return "done";
  }
  return "?";
}

WalkExecutive::WalkExecutive(link::Link& link, link::CommandSigner& signer, ApprovalGate& gate,
                             gait::GaitContext context, ExecutiveOptions options)
    : link_(link),
      signer_(signer),
      gate_(gate),
      ctx_(std::move(context)),
      opt_(std::move(options)),
      map_(GridSpec::covering(opt_.map_extent, opt_.map_resolution_m)),
      corrector_(opt_.pose_correction) {
  // Each task that ends goes to the log, for the replay's module timing.
  tasks_.onEnded([this](const Task& t) {
    if (!product_sink_) return;
    const nlohmann::json p = {
        {"name", t.name},           {"kind", kindName(t.kind)}, {"status", statusName(t.status)},
        {"started_s", t.started_s}, {"ended_s", t.ended_s},     {"note", t.note}};
    product_sink_(t.ended_s, "task", p.dump());
  });
}

void WalkExecutive::start(double now_s, bool end_hold) {
  walk_task_ =
      tasks_.add(-1, TaskKind::kGoal,
                 "walk " + std::to_string(opt_.steps) + " steps " + gait::describe(opt_.heading));
  tasks_.start(walk_task_, now_s);
  // The rover answers a Resume with its whole state, which a console that
  // came after the rover's first report needs.
  if (end_hold) endHold(now_s);
  phase_ = Phase::kConnecting;
}

void WalkExecutive::resume(double now_s) {
  if (phase_ != Phase::kSuspended) return;
  endHold(now_s);
  early_contacts_ = late_contacts_ = 0;  // the operator asked for another try
  steps_without_advance_ = 0;
  window_from_ = step_log_.size();
  if (under_way_) {
    note(now_s, "resumed: the scan waits for the end of " + moveName(*under_way_) +
                    ", under way on the rover");
    phase_ = Phase::kAwaitingMoveEnd;
    return;
  }
  if (report_.moving()) return awaitForeignMove(now_s, "resumed");
  scanAfterResume(now_s);
}

// The rover says a move is under way that this console does not follow
// (another console's, or its own before a restart) and would refuse a scan
// until it ends.
void WalkExecutive::awaitForeignMove(double now_s, const std::string& why) {
  note(now_s, why + ": the rover reports a move under way; the scan waits for its end");
  foreign_move_due_s_ = now_s + opt_.foreign_move_wait_s;
  phase_ = Phase::kAwaitingMoveEnd;
}

void WalkExecutive::followForeignMove(double now_s) {
  if (!report_.moving()) {
    note(now_s, "the rover reports the move under way ended");
    return steps_done_ >= opt_.steps ? requestClosingScan(now_s) : requestScan(now_s);
  }
  if (now_s <= foreign_move_due_s_) return;
  std::ostringstream why;
  why << "the rover still reports a move under way " << opt_.foreign_move_wait_s
      << " s after the walk began waiting for its end";
  suspend(now_s, why.str(), false);
}

void WalkExecutive::scanAfterResume(double now_s) {
  if (steps_done_ >= opt_.steps) {
    note(now_s, "resumed: the closing scan again");
    requestClosingScan(now_s);
    return;
  }
  note(now_s, "resumed: scanning and planning again from the reported state");
  requestScan(now_s);
}

void WalkExecutive::hold(double now_s, const std::string& operator_id) {
  suspend(now_s, "Hold by " + operator_id, true);
}

void WalkExecutive::note(double now_s, const std::string& what) {
  events_.push_back({now_s, what});
  if (event_sink_) event_sink_(events_.back());
}

// A command the link cannot hand over (over DDS: no rover matched within
// the link's wait) is lost, and so is the link until the rover is heard
// again; poll() then stops the walk.
std::uint64_t WalkExecutive::send(link::CommandBody body, double now_s) {
  const link::Command c = signer_.command(opt_.rover_id, std::move(body));
  last_sent_s_ = now_s;
  try {
    link_.send(c);
  } catch (const link::LinkError& e) {
    if (!link_lost_)
      note(now_s, "link lost: " + link::typeName(c.body) + " not sent (" + e.what() + ")");
    link_lost_ = e.what();
  }
  return c.sequence;
}

void WalkExecutive::requestScan(double now_s) {
  const int previous = step_task_;
  step_task_ = tasks_.add(
      walk_task_, TaskKind::kGoal, "step " + std::to_string(steps_done_ + 1),
      previous >= 0 && tasks_.task(previous).status == TaskStatus::kDone ? previous : -1);
  tasks_.start(step_task_, now_s);
  scan_attempt_ = 0;
  acquireScan(step_task_, "scan", now_s);
}

// After the last step: one more scan, registered and merged, so that the
// map covers where the rover stands and the last step gets its registered
// pose like every other.
void WalkExecutive::requestClosingScan(double now_s) {
  scan_attempt_ = 0;
  acquireScan(walk_task_, "closing scan", now_s);
}

void WalkExecutive::acquireScan(int parent_task, const std::string& name, double now_s) {
  scan_task_ = tasks_.add(parent_task, TaskKind::kQuery, name);
  tasks_.start(scan_task_, now_s);
  scan_.reset();
  scan_of_step_.reset();
  awaiting_ = send(link::AcquireScan{}, now_s);
  awaiting_what_ = "AcquireScan";
  sent_s_ = now_s;
  scan_sequence_ = *awaiting_;
  scan_acked_s_.reset();
  ++scan_attempt_;
  phase_ = Phase::kScanning;
}

// An acknowledged scan whose image never came (the largest message, the
// likeliest to be lost on a poor link) is asked for again, for the same
// step; the walk does not wait for it forever.
void WalkExecutive::scanAgain(double now_s) {
  std::ostringstream why;
  why.precision(3);
  why << "no range image within " << imageTimeoutS()
      << " s of the rover's acknowledgement of the AcquireScan (sequence " << scan_sequence_ << ")";
  if (scan_attempt_ >= opt_.scan_attempts) {
    why << "; " << scan_attempt_ << " scans asked for";
    suspend(now_s, why.str(), false);
    return;
  }
  note(now_s, why.str() + ": asking again");
  const Task lost = tasks_.task(scan_task_);
  const auto step = scan_of_step_;
  acquireScan(lost.parent, lost.name, now_s);
  scan_of_step_ = step;
}

double WalkExecutive::imageTimeoutS() const {
  return std::max(opt_.image_timeout_s, 4.0 * round_trip_s_.value_or(0.0));
}

void WalkExecutive::closeWalk(double now_s) {
  mapScan(*std::exchange(scan_, std::nullopt), now_s);
  tasks_.finish(walk_task_, now_s);
  phase_ = Phase::kDone;
}

void WalkExecutive::poll(double now_s, std::chrono::milliseconds wait) {
  const auto messages = link_.receive(wait);
  try {
    advance(messages, now_s);
  } catch (const std::exception& e) {
    // The step is dropped with the suspension: the rover stops after the
    // move under way, and a resume scans and plans afresh from there.
    suspend(now_s, std::string("ground software fault: ") + e.what(), true);
  }
}

void WalkExecutive::advance(const std::vector<link::Telemetry>& messages, double now_s) {
  if (link_lost_ && !messages.empty()) {
    note(now_s, "link back: the rover is heard again");
    link_lost_.reset();
  }
  for (const auto& message : messages) handle(message, now_s);
  if (phase_ == Phase::kIdle) return;
  if (phase_ == Phase::kConnecting && reported_) {
    if (report_.moving())
      awaitForeignMove(now_s, "connected");
    else
      requestScan(now_s);
  }
  // Even when done or suspended, and while waiting for the rover's state
  // (which a rover with a move under way reports only at its end): the
  // rover holds when the ground falls silent. Not before the rover is
  // heard, nor while the link is lost: each attempt would wait for it.
  if (heard_ && !link_lost_ && now_s - last_sent_s_ >= opt_.heartbeat_period_s)
    send(link::GroundHeartbeat{}, now_s);
  if (phase_ == Phase::kConnecting) return;
  // The step planned or under way before the outage is dropped: after it,
  // the operator resumes and the step is scanned and planned afresh.
  if (link_lost_ && phase_ != Phase::kSuspended && phase_ != Phase::kDone)
    suspend(now_s, "link lost: " + *link_lost_, false);
  if (phase_ == Phase::kDone || phase_ == Phase::kSuspended) {
    followMoveWhileSuspended(now_s);
    return;
  }
  if (awaiting_ && now_s - sent_s_ > ackTimeoutS()) {
    std::ostringstream why;
    why.precision(3);
    why << "the rover did not acknowledge the " << awaiting_what_ << " (sequence " << *awaiting_
        << ") within " << ackTimeoutS() << " s";
    suspend(now_s, why.str(), true);
    return;
  }
  if (phase_ == Phase::kScanning && !scan_ && scan_acked_s_ &&
      now_s - *scan_acked_s_ > imageTimeoutS()) {
    scanAgain(now_s);
    return;
  }
  if (phase_ == Phase::kScanning && scan_ && !awaiting_ && reported_)
    steps_done_ >= opt_.steps ? closeWalk(now_s) : planAndPropose(now_s);
  if (phase_ == Phase::kAwaitingDecision) {
    if (auto released = gate_.takeReleased()) {
      startExecuting(std::move(*released), now_s);
    } else if (!gate_.pending()) {
      tasks_.fail(approval_task_, now_s, "rejected");
      suspend(now_s, "step rejected by the operator", false);
    }
  }
  const bool awaiting_move =
      under_way_ && (phase_ == Phase::kExecuting || phase_ == Phase::kAwaitingMoveEnd);
  if (awaiting_move && report_.reportedSince(under_way_->rover_acknowledged_s)) {
    if (phase_ == Phase::kExecuting) return afterMove(now_s);
    under_way_.reset();
    scanAfterResume(now_s);
  } else if (awaiting_move && now_s > under_way_->due_s) {
    const std::string why = outcomeLate();
    under_way_.reset();
    suspend(now_s, why, true);
  } else if (phase_ == Phase::kAwaitingMoveEnd && !under_way_) {
    followForeignMove(now_s);
  }
}

// A hold stops the next motion, not the one under way (docs/dds.md §7): it
// is followed to its end while the walk is suspended, so that a resume does
// not send what the rover would refuse before then.
void WalkExecutive::followMoveWhileSuspended(double now_s) {
  if (!under_way_) return;
  if (report_.reportedSince(under_way_->rover_acknowledged_s))
    note(now_s, "the rover reported the state after " + moveName(*under_way_));
  else if (now_s > under_way_->due_s)
    note(now_s, outcomeLate());
  else
    return;
  under_way_.reset();
}

void WalkExecutive::handle(const link::Telemetry& message, double now_s) {
  if (message.rover_id != opt_.rover_id) return;
  heard_ = true;
  if (std::holds_alternative<link::LegState>(message.body) ||
      std::holds_alternative<link::BodyState>(message.body)) {
    report_.take(message);
    placeReported();
  } else if (const auto* a = std::get_if<link::CommandAck>(&message.body)) {
    onAck(*a, message.time_s, now_s);
  } else if (const auto* h = std::get_if<link::Heartbeat>(&message.body)) {
    onRoverHeartbeat(*h, message.time_s, now_s);
  } else if (const auto* image = std::get_if<sensor::RangeImage>(&message.body)) {
    if (phase_ == Phase::kScanning) scan_ = *image, scan_time_s_ = message.time_s;
  }
}

// Harmless when the rover does not hold. Not awaited, as the scan that
// follows is acknowledged after it; until its own acknowledgement, a
// heartbeat that says the rover holds is from before it.
void WalkExecutive::endHold(double now_s) { resume_ = send(link::Resume{}, now_s); }

// A hold the executive did not ask for (link loss, or another console's
// Hold) stops the step; the operator decides when to resume.
void WalkExecutive::onRoverHeartbeat(const link::Heartbeat& heartbeat, double rover_time_s,
                                     double now_s) {
  // Heartbeats and acknowledgements travel on different topics: one sent
  // before the Resume's acknowledgement may come after it.
  const bool before_resume = resume_ || rover_time_s < resumed_at_s_;
  if (heartbeat.hold_reason == rover_holding_ || (before_resume && heartbeat.holding)) return;
  rover_holding_ = heartbeat.hold_reason;
  if (!heartbeat.holding) {
    note(now_s, "rover no longer holds");
    return;
  }
  note(now_s, "rover holds: " + rover_holding_);
  if (phase_ != Phase::kSuspended && phase_ != Phase::kDone)
    suspend(now_s, "rover holds: " + rover_holding_, false);
}

double WalkExecutive::ackTimeoutS() const {
  return std::max(opt_.ack_timeout_s, 4.0 * round_trip_s_.value_or(0.0));
}

double WalkExecutive::modelledSeconds(const link::CommandBody& command) const {
  const auto& m = ctx_.model;
  if (const auto* body = std::get_if<link::BodyMove>(&command))
    return m.bodyMoveS(std::hypot(body->x_m, body->y_m), body->rotation_rad, body->raise_m);
  const auto* leg = std::get_if<link::LegMove>(&command);
  if (!leg || leg->waypoints.empty()) return 0.0;
  const auto& reported = report_.legs[std::size_t(leg->leg)];
  gait::LegJoints at = reported ? reported->joints : leg->waypoints.front();
  double seconds = 0.0;
  for (const auto& waypoint : leg->waypoints) seconds += m.legSegmentS(at, waypoint), at = waypoint;
  return seconds + std::max(0.0, m.vertical_max_m - at.vertical_m) / m.vertical_speed_m_s;
}

void WalkExecutive::onAck(const link::CommandAck& ack, double rover_time_s, double now_s) {
  if (ack.operator_id != signer_.operatorId() || ack.console_id != signer_.consoleId()) return;
  // This console's commands reach the rover in the order sent, so the
  // acknowledgement of a later one means the Resume was handled or lost
  // (sent before the rover listened, its acknowledgement dropped). Waiting
  // on would hide every hold the rover reports from now on.
  if (resume_ && ack.sequence >= *resume_) resume_.reset(), resumed_at_s_ = rover_time_s;
  if (!awaiting_ || ack.sequence != *awaiting_) {
    // Heartbeats and Resume are not awaited; only their refusals come back.
    if (!ack.accepted)
      note(now_s, "rover refused command " + std::to_string(ack.sequence) + ": " + ack.reason);
    return;
  }
  awaiting_.reset();
  const double sample = now_s - sent_s_;
  round_trip_s_ = round_trip_s_ ? 0.8 * *round_trip_s_ + 0.2 * sample : sample;
  const bool moving = phase_ == Phase::kExecuting;
  const int task = moving ? command_tasks_[next_command_ - 1] : scan_task_;
  if (!ack.accepted) {
    tasks_.fail(task, now_s, ack.reason);
    suspend(now_s, "rover refused " + tasks_.task(task).name + ": " + ack.reason, false);
    return;
  }
  tasks_.finish(task, now_s);
  if (moving)
    expectOutcome(ack.sequence, rover_time_s, now_s);
  else
    scan_acked_s_ = now_s;
}

void WalkExecutive::expectOutcome(std::uint64_t sequence, double rover_time_s, double now_s) {
  MoveUnderWay& m = under_way_.emplace();
  m.type = awaiting_what_;
  m.sequence = sequence;
  m.acknowledged_s = now_s;
  m.rover_acknowledged_s = rover_time_s;
  m.modelled_s = modelledSeconds(executing_->commands[next_command_ - 1]);
  m.due_s = now_s + opt_.move_time_factor * m.modelled_s + ackTimeoutS();
}

std::string WalkExecutive::outcomeLate() const {
  std::ostringstream why;
  why.precision(3);
  why << "the rover did not report the outcome of " << moveName(*under_way_) << " within "
      << under_way_->due_s - under_way_->acknowledged_s << " s of acknowledging it (the move takes "
      << under_way_->modelled_s << " s by the rover model)";
  return why.str();
}

// LTM builder and merger (cmu-1990): the scan's locus map over the part of
// the traverse map its returns fall in, fused into it.
// A scan whose match disputes dead reckoning is left out until the matches
// settle it: merged where the rover says it is, it would drag the map
// along with a pose that may be wrong.
void WalkExecutive::mapScan(const sensor::RangeImage& scan, double now_s) {
  const bool merge = !opt_.register_scans || !correctPose(scan, now_s).disputed;
  const auto t0 = Clock::now();
  sensor::RangeImage placed = scan;
  placed.sensor_to_world = correction().transform() * scan.sensor_to_world;
  const GridSpec window = merge ? terrain::mergeScan(map_, placed) : GridSpec{};
  for (const auto& foot : felt_) holdFeltGround(foot);
  scanner_ = scan.geometry;
  work_.mapping_s += secondsSince(t0);
  if (scan_of_step_) {
    auto& step = step_log_[*std::exchange(scan_of_step_, std::nullopt)];
    step.registered = correction().apply(step.reported);
  }
  if (scan_sink_) scan_sink_(placed);
  if (product_sink_) {
    // The traverse map's grid (what a replay rebuilds) and the part merged.
    const GridSpec& g = map_.grid();
    const nlohmann::json p = {{"method", "locus"},
                              {"merged_into", "traverse map"},
                              {"range_image_time_s", scan_time_s_},
                              {"origin_x", g.origin_x},
                              {"origin_y", g.origin_y},
                              {"resolution", g.resolution},
                              {"cols", g.cols},
                              {"rows", g.rows},
                              {"window_origin_x", window.origin_x},
                              {"window_origin_y", window.origin_y},
                              {"window_cols", window.cols},
                              {"window_rows", window.rows}};
    product_sink_(now_s, "elevation_map", p.dump());
  }
}

// The scan against the map so far: an accepted match becomes the
// correction of everything the rover reports from now on.
const ScanMatch& WalkExecutive::correctPose(const sensor::RangeImage& scan, double now_s) {
  const auto t0 = Clock::now();
  ScanMatch m = corrector_.correct(scan, map_);
  work_.registering_s += secondsSince(t0);
  if (m.accepted) {
    placeReported();
  } else if (!matches_.empty()) {  // the first scan has no map to match
    note(now_s, "scan not registered: " + m.refused +
                    (m.disputed ? "; the scan is not merged" : "; dead reckoning carries on"));
  }
  if (product_sink_) {
    const nlohmann::json p = {{"range_image_time_s", scan_time_s_},
                              {"accepted", m.accepted},
                              {"refused", m.refused},
                              {"relocated", m.relocated},
                              {"merged", !m.disputed},
                              {"shift_x_m", correction().shift.x()},
                              {"shift_y_m", correction().shift.y()},
                              {"yaw_rad", correction().yaw_rad},
                              {"dz_m", correction().dz_m},
                              {"change_m", m.change_m},
                              {"change_rad", m.change_rad},
                              {"rms_m", m.rms_m},
                              {"points", m.points},
                              {"iterations", m.iterations},
                              {"sigma_xy_m", m.sigma_xy_m},
                              {"sigma_yaw_rad", m.sigma_yaw_rad},
                              {"chi2", m.chi2},
                              {"ms", m.ms}};
    product_sink_(now_s, "pose_correction", p.dump());
  }
  matches_.push_back(std::move(m));
  return matches_.back();
}

void WalkExecutive::placeReported() {
  if (auto stance = report_.stance(ctx_.model)) reported_ = correction().apply(*stance);
}

// The scanner looks along the body's forward axis (+y in the body frame).
std::optional<footfall::ScannerView> WalkExecutive::scannerView(const gait::Stance& from) const {
  if (!scanner_) return std::nullopt;
  footfall::ScannerView view;
  view.position = from.body.xy;
  view.heading_rad = from.body.heading_rad + M_PI / 2;
  view.horizontal_fov_rad = std::abs(scanner_->theta_step) * scanner_->cols;
  return view;
}

gait::StepPlan WalkExecutive::plan(const gait::Stance& from) {
  const auto t0 = Clock::now();
  gait::StepPlan p = gait::planStep(from, opt_.heading, map_, ctx_, scannerView(from));
  work_.planning_s += secondsSince(t0);
  return p;
}

namespace {

// A plan made in the map frame before the correction changed, in the frame
// the correction now gives.
void reexpress(gait::StepPlan& plan, const PoseCorrection& before, const PoseCorrection& now) {
  const PoseCorrection change = now * before.inverse();
  plan.foothold = change.transform() * plan.foothold;
  plan.after_leg = change.apply(plan.after_leg);
  plan.after = change.apply(plan.after);
  for (auto& pose : plan.body_path) pose = change.apply(pose);
}

}  // namespace

// cmu-1990 TCA: on auto-approve, a step planned ahead that passes its
// interlocks goes out at once and its scan is registered and merged while
// the rover executes it; an operator who decides sees the newest scan
// merged first. A plan ahead that fails an interlock is dropped and the
// step planned afresh on the newest map.
void WalkExecutive::planAndPropose(double now_s) {
  const bool had_ahead = ahead_.has_value();
  std::optional<StepProposal> proposal;
  if (auto ahead = takeAhead()) proposal = checkAhead(std::move(*ahead), now_s);
  if (proposal && gate_.mode() == ApprovalMode::kAutoApprove) {
    unmapped_ = std::move(scan_);
  } else {
    const PoseCorrection before = correction();
    mapScan(*scan_, now_s);
    if (proposal) {
      reexpress(proposal->plan, before, correction());
      proposal = checkAhead(std::move(proposal->plan), now_s);
    }
  }
  scan_.reset();
  plan_task_ = tasks_.add(step_task_, TaskKind::kQuery, "plan", scan_task_);
  tasks_.start(plan_task_, now_s);
  if (proposal) {
    ++planned_ahead_;
    note(now_s, "step " + std::to_string(steps_done_ + 1) +
                    ": the plan made during the step before, moved onto the reported stance");
  }
  step_ = StepRecord{};
  step_.event = std::exchange(replanned_because_, {});
  step_.planned_ahead = proposal.has_value();
  step_.replanned = (had_ahead && !proposal) || !step_.event.empty();
  step_.plan_ms = ahead_ms_;
  if (!proposal) {
    const auto t0 = Clock::now();
    gait::StepPlan fresh = plan(*reported_);
    step_.plan_ms = 1e3 * secondsSince(t0);
    if (!fresh.ok) {
      noStepToPropose(now_s, fresh.reason);
      return;
    }
    proposal = makeProposal(0, *reported_, std::move(fresh), map_, ctx_);
  }
  if (const auto why = noProgress(proposal->plan)) {
    // A scan held back for a plan ahead goes into the map all the same.
    if (unmapped_) mapScan(*std::exchange(unmapped_, std::nullopt), now_s);
    noStepToPropose(now_s, *why);
    return;
  }
  tasks_.finish(plan_task_, now_s);
  step_.leg = proposal->plan.leg;
  step_.foothold = proposal->plan.foothold;
  step_.body_u = proposal->plan.body_u;
  step_.reason = proposal->plan.reason;
  approval_task_ = tasks_.add(step_task_, TaskKind::kApproval, "approval", plan_task_);
  tasks_.start(approval_task_, now_s);
  phase_ = Phase::kAwaitingDecision;
  proposal->id = next_proposal_++;
  if (product_sink_) product_sink_(now_s, "proposal", proposalRecord(*proposal));
  gate_.propose(std::move(*proposal), now_s);
}

std::optional<std::string> WalkExecutive::noProgress(const gait::StepPlan& next) const {
  if (!advancesTheBody(next.body_u) &&
      steps_without_advance_ + 1 >= opt_.max_steps_without_advance) {
    const int n = steps_without_advance_;
    return "the body has not advanced in " + std::to_string(n) + (n == 1 ? " step" : " steps") +
           " and would not in the next: no foothold lets it move on";
  }
  // The window's advance_window steps, each from where the one before ended.
  const std::size_t n = step_log_.size(), window = std::size_t(opt_.advance_window);
  if (n < window_from_ + window + 1) return std::nullopt;
  double advanced = 0.0;
  for (std::size_t i = n - window; i < n; ++i)
    advanced += advanceAlongHeading(step_log_[i - 1].reported, step_log_[i].reported);
  if (advanced >= opt_.min_window_advance) return std::nullopt;
  std::string how_far = "advanced " + metres(advanced);
  if (opt_.heading.isPointTurn()) {
    std::ostringstream turned;
    turned << "turned " << std::fixed << std::setprecision(1) << advanced * 180.0 / M_PI << " deg";
    how_far = turned.str();
  }
  return "the body has " + how_far + " in the last " + std::to_string(opt_.advance_window) +
         " steps: no foothold lets it move on";
}

// The planning task fails and the walk suspends with `why` and what the
// stance suggests the operator do about it.
void WalkExecutive::noStepToPropose(double now_s, const std::string& why) {
  tasks_.fail(plan_task_, now_s, why);
  suspend(now_s, "no step to propose: " + why + pointTurnHint() + mapEdgeHint(), false);
}

// In a point turn the inner stack recovers backwards, onto ground behind
// the rover that the forward-looking scanner has not seen (docs/gait.md):
// the likeliest reason a turn stops, and what the operator can do.
std::string WalkExecutive::pointTurnHint() const {
  if (!opt_.heading.isPointTurn()) return {};
  return " (turning in place, the inner legs step back onto ground behind the rover, which the "
         "scanner may not have seen: walk ahead first, or turn on a wide arc)";
}

// The map keeps no ground beyond its extent, so a walk that comes within
// a leg's reach of its far edge runs out of footholds there, whatever the
// ground is like: say so rather than let the ground take the blame.
std::string WalkExecutive::mapEdgeHint() const {
  if (!reported_ || opt_.heading.isPointTurn()) return {};
  const gait::BodyPose& body = reported_->body;
  const Eigen::Vector2d ahead = body.rotation() * Eigen::Vector2d::UnitY();
  const auto inside = map_.grid().bounds().lineInterval(body.xy, ahead, INFINITY);
  const double reach = ctx_.model.extension_max_m + ctx_.model.foot_diameter_m;
  if (!inside || !(inside->second <= reach)) return {};
  return " (the map ends " + metres(inside->second) +
         " ahead of the body, within a leg's reach: it keeps no ground beyond its extent)";
}

double WalkExecutive::advanceAlongHeading(const gait::BodyPose& from,
                                          const gait::BodyPose& to) const {
  const auto& h = opt_.heading;
  if (h.isPointTurn())
    return std::remainder(to.heading_rad - from.heading_rad, 2 * M_PI) / h.turnPerUnit();
  return (to.xy - from.xy).dot(from.rotation() * Eigen::Vector2d::UnitY());
}

// While the step's first command executes: the scan its plan went out
// ahead of is registered and merged, and the step re-expressed in the
// frame that scan's match gives.
void WalkExecutive::mapDeferredScan(double now_s) {
  if (!unmapped_) return;
  const PoseCorrection before = correction();
  mapScan(*std::exchange(unmapped_, std::nullopt), now_s);
  reexpress(executing_->plan, before, correction());
}

// While the step's last command executes: the next step, planned from the
// stance this one should end in.
void WalkExecutive::planAhead(double now_s) {
  ahead_.reset();
  if (!opt_.plan_ahead || steps_done_ + 1 >= opt_.steps) return;
  const int task = tasks_.add(walk_task_, TaskKind::kQuery,
                              "plan step " + std::to_string(steps_done_ + 2) + " ahead");
  tasks_.start(task, now_s);
  ahead_from_ = executing_->plan.after;
  const auto t0 = Clock::now();
  gait::StepPlan plan = this->plan(ahead_from_);
  ahead_ms_ = 1e3 * secondsSince(t0);
  if (!plan.ok) {
    tasks_.fail(task, now_s, plan.reason);
    return;
  }
  tasks_.finish(task, now_s);
  ahead_ = std::move(plan);
}

// The plan ahead as a proposal from the reported stance on the map as it
// stands, if it passes every interlock; if not, the log says which.
std::optional<StepProposal> WalkExecutive::checkAhead(gait::StepPlan ahead, double now_s) {
  StepProposal p = makeProposal(0, *reported_, std::move(ahead), map_, ctx_);
  const auto failure = p.interlocks.firstFailure();
  if (failure.empty()) return p;
  note(now_s, "step " + std::to_string(steps_done_ + 1) + ": the plan made ahead fails " + failure +
                  "; planning afresh");
  return std::nullopt;
}

// The plan ahead if the rover ended close enough to its prediction for the
// plan to be moved onto where it is; otherwise none, and the step is
// planned afresh on the newest map.
std::optional<gait::StepPlan> WalkExecutive::takeAhead() {
  if (!ahead_) return std::nullopt;
  const gait::StepPlan plan = std::move(*ahead_);
  ahead_.reset();
  const auto& now = *reported_;
  if ((now.body.xy - ahead_from_.body.xy).norm() > opt_.off_plan_m) return std::nullopt;
  if (std::abs(now.body.heading_rad - ahead_from_.body.heading_rad) > opt_.off_plan_rad)
    return std::nullopt;
  for (int i = 0; i < gait::kLegCount; ++i)
    if ((now.feet[std::size_t(i)] - ahead_from_.feet[std::size_t(i)]).norm() > opt_.off_plan_m)
      return std::nullopt;
  return gait::reanchorStep(plan, ahead_from_, now, opt_.heading, ctx_);
}

Refusal WalkExecutive::editFoothold(std::uint64_t proposal, const Eigen::Vector2d& xy,
                                    const std::string& operator_id, double now_s) {
  const auto& pending = gate_.pending();
  if (!pending || pending->id != proposal)
    return Refusal::because("step " + std::to_string(proposal) + " is not waiting for a decision");
  if (pending->plan.leg < 0)
    return Refusal::because("this step moves no leg, so it has no foothold to edit");
  gait::StepPlan plan =
      gait::planStepWithFoothold(pending->from, opt_.heading, map_, ctx_, pending->plan.leg, xy);
  auto edited = makeProposal(proposal, pending->from, std::move(plan), map_, ctx_);
  const std::string record = proposalRecord(edited);
  auto edit = gate_.edit(proposal, operator_id, now_s, std::move(edited));
  if (!edit.refused() && product_sink_) product_sink_(now_s, "proposal", record);
  return edit;
}

void WalkExecutive::startExecuting(StepProposal proposal, double now_s) {
  tasks_.finish(approval_task_, now_s);
  command_tasks_.clear();
  int after = approval_task_;
  for (const auto& c : proposal.commands) {
    after = tasks_.add(step_task_, TaskKind::kCommand, link::typeName(c), after);
    command_tasks_.push_back(after);
  }
  executing_ = std::move(proposal);
  next_command_ = 0;
  phase_ = Phase::kExecuting;
  sendNext(now_s);
  mapDeferredScan(now_s);
  if (executing_->commands.size() == 1) planAhead(now_s);
}

void WalkExecutive::sendNext(double now_s) {
  tasks_.start(command_tasks_[next_command_], now_s);
  under_way_.reset();
  if (auto* move = std::get_if<link::LegMove>(&executing_->commands[next_command_]))
    liftFromWhereItStands(*move);
  awaiting_ = send(executing_->commands[next_command_], now_s);
  awaiting_what_ = link::typeName(executing_->commands[next_command_]);
  sent_s_ = now_s;
  ++next_command_;
}

// The lift goes straight up from where the leg stands, as it reports. A
// step planned ahead lifts from the stance predicted for it, which the
// moves before missed by their execution error; the sole, beside a rock,
// would drag across its edge.
void WalkExecutive::liftFromWhereItStands(link::LegMove& move) const {
  const auto& leg = report_.legs[std::size_t(move.leg)];
  if (!leg || move.waypoints.empty()) return;
  auto& lift = move.waypoints.front();
  lift = gait::liftOff(leg->joints, lift.vertical_m, ctx_.model);
}

// What the rover reports after a move, against the plan.
void WalkExecutive::afterMove(double now_s) {
  under_way_.reset();
  const auto& m = ctx_.model;
  const double margin = gait::marginWithout(*reported_, m, -1);
  if (margin < 0) {
    suspend(now_s, "centre of gravity " + metres(-margin) + " outside the support polygon", true);
    return;
  }
  const auto& plan = executing_->plan;
  const bool leg_move =
      std::holds_alternative<link::LegMove>(executing_->commands[next_command_ - 1]);
  if (leg_move) {
    const Eigen::Vector3d& foot = reported_->feet[std::size_t(plan.leg)];
    const double short_by = (foot - plan.foothold).norm();
    if (plan.foothold.z() - foot.z() > opt_.late_contact_m) {
      // The foot went on down to ground the map put higher and stands
      // there: the leg is placed, but the body move was checked for the
      // planned height. Planned again from here; no early contact.
      const std::string met = "leg " + std::to_string(plan.leg) + " met the ground " +
                              metres(plan.foothold.z() - foot.z()) + " below its foothold";
      metOtherGround(now_s, foot, "late contact", late_contacts_, opt_.max_late_contacts, met, met,
                     "the map puts the ground too high");
      return;
    }
    if (short_by > opt_.early_contact_m) {
      const std::string stopped =
          "leg " + std::to_string(plan.leg) + " stopped " + metres(short_by);
      metOtherGround(now_s, foot, "early contact", early_contacts_, opt_.max_early_contacts,
                     stopped + " from its foothold", stopped + " short",
                     "the map misses what the foot meets");
      return;
    }
  } else {
    const double off = (reported_->body.xy - plan.after.body.xy).norm();
    if (off > opt_.off_plan_m) {
      note(now_s, "body " + metres(off) +
                      " off its plan (slip): the next step starts from "
                      "where the rover reports it is");
      step_.event += (step_.event.empty() ? "" : "; ") + ("body " + metres(off) + " off its plan");
    }
  }
  if (next_command_ == executing_->commands.size()) {
    finishStep(now_s);
    return;
  }
  sendNext(now_s);
  if (next_command_ == executing_->commands.size()) planAhead(now_s);
}

// A foot met ground other than the map said (`kind`: an early or a late
// contact): its height goes into the map and, the body not having moved,
// the step is planned again from the stance the rover reports, after a
// scan; `limit` such contacts in a row suspend the walk with `verdict`.
void WalkExecutive::metOtherGround(double now_s, const Eigen::Vector3d& foot,
                                   const std::string& kind, int& in_a_row, int limit,
                                   const std::string& what, const std::string& because,
                                   const std::string& verdict) {
  feelGround(foot);
  if (++in_a_row >= limit) {
    suspend(now_s,
            what + ", " + kind + " " + std::to_string(in_a_row) +
                (in_a_row == 1 ? " time" : " times") + " in a row: " + verdict,
            false);
    return;
  }
  tasks_.suspend(step_task_, now_s, kind);
  note(now_s, what + " (" + kind + "): replanning");
  replanned_because_ = because + " (" + kind + "), replanned";
  executing_.reset();
  ahead_.reset();
  requestScan(now_s);
}

// The sole rests on ground other than the map says (an early or a late
// contact): the cell under the foot takes the sole's height, so that the
// next plan sees what the foot met instead of choosing the same foothold
// again. The scans that follow may not see it (under the sole's rim, in a
// rock's shadow), so every merge keeps the felt ground at least that high.
// A flat sole resting at z has nothing under it higher than z: felt ground
// it covers that stands higher was met under an earlier sole's rim, not
// at its centre, and goes.
void WalkExecutive::feelGround(const Eigen::Vector3d& foot) {
  const double radius = 0.5 * ctx_.model.foot_diameter_m;
  std::erase_if(felt_, [&](const Eigen::Vector3d& f) {
    return (f.head<2>() - foot.head<2>()).norm() < radius && f.z() > foot.z();
  });
  felt_.push_back(foot);
  if (const auto cell = map_.grid().cellAt(foot.x(), foot.y()))
    map_.setKnown(cell->row, cell->col, foot.z(), opt_.early_contact_m / 2);
}

void WalkExecutive::holdFeltGround(const Eigen::Vector3d& foot) {
  const auto cell = map_.grid().cellAt(foot.x(), foot.y());
  if (!cell) return;
  if (map_.hasHeight(cell->row, cell->col) && map_.elevation(cell->row, cell->col) >= foot.z())
    return;
  map_.setKnown(cell->row, cell->col, foot.z(), opt_.early_contact_m / 2);
}

void WalkExecutive::finishStep(double now_s) {
  early_contacts_ = late_contacts_ = 0;
  steps_without_advance_ = advancesTheBody(step_.body_u) ? 0 : steps_without_advance_ + 1;
  tasks_.finish(step_task_, now_s);
  step_.estimated = reported_->body;
  step_.reported = report_.stance(ctx_.model)->body;
  step_log_.push_back(step_);
  executing_.reset();
  ++steps_done_;
  if (steps_done_ >= opt_.steps)
    requestClosingScan(now_s);
  else
    requestScan(now_s);
  scan_of_step_ = step_log_.size() - 1;
}

void WalkExecutive::suspend(double now_s, const std::string& why, bool hold) {
  if (hold) send(link::Hold{}, now_s);  // not awaited: the rover stops whatever it hears next
  suspended_because_ = (hold ? "Hold sent, step suspended: " : "step suspended: ") + why;
  note(now_s, suspended_because_);
  if (step_task_ >= 0 && tasks_.task(step_task_).status == TaskStatus::kActive)
    tasks_.suspend(step_task_, now_s, why);
  executing_.reset();
  awaiting_.reset();
  ahead_.reset();
  gate_.withdraw();
  phase_ = Phase::kSuspended;
}

}  // namespace ambler::executive
