#pragma once

// The ground's side of a walk over any link (cmu-1990 TCA): for
// each step it asks for a scan, maps it, plans the step, puts the proposal
// before the approval gate, sends the approved moves signed, and checks
// what the rover reports. A NACK, an unanswered command, a centre of
// gravity outside the support polygon, a leg stopped short by early
// contact, or a body off its plan (a slip) is an exception: the step is
// suspended (after a Hold where the rover may be unsafe) or planned again.
// As in TCA, the next step is planned on the predicted stance while the
// rover executes the current one; if the rover ends where predicted, that
// plan is moved onto the reported stance and proposed without waiting for
// the planner.

#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/Region.h"
#include "executive/ApprovalGate.h"
#include "executive/ReportedStance.h"
#include "executive/ScanMatching.h"
#include "executive/TaskTree.h"
#include "link/Link.h"
#include "link/Signing.h"

namespace ambler::executive {

struct ExecutiveOptions {
  std::uint32_t rover_id = 1;
  int steps = 5;
  gait::Heading heading;  // straight ahead by default
  // A command unanswered this long, or 4 measured round trips if longer
  // (a long-delay link): Hold, suspend.
  double ack_timeout_s = 10.0;
  // A range image not come this long after its AcquireScan was
  // acknowledged (or 4 round trips, if longer) is asked for again, up to
  // `scan_attempts` in all; then the step suspends, naming the image.
  double image_timeout_s = 10.0;
  int scan_attempts = 3;
  // A move whose outcome (the leg and body states the rover reports after
  // acknowledging it) has not come within this many times the move's
  // duration by the rover model's joint and body speeds, plus the ack
  // timeout: Hold, suspend. A rover acknowledges a move when it takes it
  // on, so without a limit a rover that stopped reporting would keep the
  // step executing for good.
  double move_time_factor = 2.0;
  // A move under way that is not this console's (another console's, or
  // this console's before it restarted): the scan waits for the rover to
  // report the move ended, at most this long; then the walk suspends,
  // saying so. Two of the longest body moves the planner makes (1.5 m,
  // 45 s by the rover model).
  double foreign_move_wait_s = 90.0;
  double off_plan_m = 0.05;    // body or foot further than this from the plan: replan
  double off_plan_rad = 0.02;  // or the body turned this much more or less than planned
  // Plan the next step while the rover executes this one (cmu-1990 TCA);
  // off: scan, plan and execute one after the other.
  bool plan_ahead = true;
  double early_contact_m = 0.05;  // a foot this far short of its last waypoint
  // A foot this far below its foothold went on down to ground the map put
  // higher: planned again from there, not an early contact.
  double late_contact_m = 0.05;
  // Early contacts in a row, with no step done between them, after which
  // the walk suspends: the map misses what the feet meet. Each contact
  // leaves the height it met in the map, so the next plan tries other
  // ground; six: every leg could have met a rock under its sole's rim once.
  int max_early_contacts = 6;
  // Late contacts in a row, with no step done between them, after which
  // the walk suspends: the map puts the ground too high wherever the feet
  // go (each places a leg, so without a limit they could go on for good).
  int max_late_contacts = 3;
  // The walk suspends rather than propose a step that would make this many
  // in a row that do not advance the body along the heading (a foot
  // re-placed, a body shift): the legs find no footholds that let the body
  // move on, and the planner would go on shuffling them (a point turn whose
  // trailing stack needs ground behind the rover that the scanner has not
  // seen). Six: every leg could have moved once.
  int max_steps_without_advance = 6;
  // Nor one when the body, as the rover reports it, has advanced less than
  // min_window_advance along the heading (u: metres; radians in a point
  // turn) over the last advance_window steps: a foot re-placed back and
  // forth, each time with a short body move that a body shift then undoes,
  // advances every other step and goes nowhere. Twelve: every leg twice.
  int advance_window = 12;
  double min_window_advance = 0.1;
  Box2 map_extent{-10.0, -8.0, 10.0, 45.0};
  double map_resolution_m = 0.1;
  // Register each scan against the traverse map and correct the rover's
  // dead reckoning by it; off: map and plan where the rover says it is.
  bool register_scans = true;
  PoseCorrectorOptions pose_correction;
  // A GroundHeartbeat goes out when nothing else has for this long; keep it
  // well under the rover's link timeout.
  double heartbeat_period_s = 1.0;
};

enum class Phase {
  kIdle,
  kConnecting,
  kScanning,
  kAwaitingDecision,
  kExecuting,
  // The rover has a move under way, and takes nothing else on before its
  // outcome: the move of a suspended step after a resume (a hold stops the
  // next motion, not that one), or one the rover reports that is not this
  // console's.
  kAwaitingMoveEnd,
  kSuspended,
  kDone
};
std::string phaseName(Phase phase);

struct ExecutiveEvent {
  double time_s = 0.0;
  std::string what;
};

// One step as the ground carried it out, for the walk's log.
struct StepRecord {
  int leg = -1;  // -1: a body move alone
  Eigen::Vector3d foothold{0, 0, 0};
  double body_u = 0.0;
  bool planned_ahead = false;  // proposed from the plan made during the step before
  bool replanned = false;      // its plan ahead was dropped: the rover ended off the prediction
  double plan_ms = 0.0;        // wall time of the plan it came from
  gait::BodyPose reported;     // where the rover reported its body after the step
  gait::BodyPose estimated;    // where the ground placed it: the report, corrected
  // Where the scan taken after the step placed it, once registered: the
  // ground's account of the stance it planned the next step from. Unset
  // until that scan is mapped (the walk closes with one for its last step).
  std::optional<gait::BodyPose> registered;
  std::string event;  // what went differently from the plan, if anything
  std::string reason;  // the plan's account of its body move: what stopped it
};

// A move the rover has acknowledged and not yet reported the outcome of.
struct MoveUnderWay {
  std::string type;  // "LegMove"
  std::uint64_t sequence = 0;
  double acknowledged_s = 0;  // console time
  // Rover time of the acknowledgement: what the rover reports from then on
  // is the state after the move.
  double rover_acknowledged_s = 0;
  double modelled_s = 0;      // its duration by the rover model
  double due_s = 0;           // console time after which the walk is held
};

// Wall time the ground spent on a walk's perception and planning: the work
// the rover's execution can hide when planning ahead.
struct GroundWork {
  double registering_s = 0.0;
  double mapping_s = 0.0;
  double planning_s = 0.0;
  double total_s() const { return registering_s + mapping_s + planning_s; }
};

// A derived product (kind, and the parameters that recompute it from the
// logged messages, as JSON) for the mission log.
using ProductSink =
    std::function<void(double time_s, const std::string& kind, const std::string& parameters_json)>;

class WalkExecutive {
 public:
  WalkExecutive(link::Link& link, link::CommandSigner& signer, ApprovalGate& gate,
                gait::GaitContext context, ExecutiveOptions options = {});

  void onProduct(ProductSink sink) { product_sink_ = std::move(sink); }
  // Each scan as it is mapped, placed in the world by the rover's dead
  // reckoning (for the views: registering and merging them).
  void onScanMapped(std::function<void(const sensor::RangeImage&)> sink) {
    scan_sink_ = std::move(sink);
  }
  // Each event as it is noted (a stop and its reason, a refusal, the link
  // lost and back), for the log and the operator.
  void onEvent(std::function<void(const ExecutiveEvent&)> sink) { event_sink_ = std::move(sink); }

  // The walk goal: asks for a first scan once the rover's state has come
  // (the link works); with `end_hold`, ends a hold the rover may be in
  // first (the operator chose to walk it again), which also brings the
  // rover's whole state again.
  void start(double now_s, bool end_hold = false);
  // Reads what arrived (waiting up to `wait`), reacts, and sends what the
  // gate released. Call it often. A fault of the ground's own work
  // (planning, mapping, matching: an exception) holds the rover and
  // suspends the walk with the fault named; it does not escape.
  void poll(double now_s, std::chrono::milliseconds wait);
  // The operator moved the pending step's foothold: the step is planned
  // again with it and its interlocks checked; it stays pending.
  Refusal editFoothold(std::uint64_t proposal, const Eigen::Vector2d& xy,
                       const std::string& operator_id, double now_s);
  // After a suspension or a rejection: end the rover's hold if it holds,
  // then, once a move still under way has ended, scan and plan again from
  // where the rover reports it is.
  void resume(double now_s);
  // The operator's stop: a signed Hold at once, whatever the walk is doing;
  // a step under way is suspended and nothing more is sent. The rover ends
  // the move under way, if any, and stays still until a resume or a new
  // walk ends the hold.
  void hold(double now_s, const std::string& operator_id);

  Phase phase() const { return phase_; }
  int stepsDone() const { return steps_done_; }
  // Steps proposed from a plan made while the one before executed.
  int stepsPlannedAhead() const { return planned_ahead_; }
  const TaskTree& tasks() const { return tasks_; }
  const std::vector<ExecutiveEvent>& events() const { return events_; }
  // The rover's reported stance placed on the map by the correction.
  const std::optional<gait::Stance>& reported() const { return reported_; }
  const RoverReport& report() const { return report_; }
  const terrain::ElevationMap& map() const { return map_; }
  // Where soles met ground other than the map said (early and late
  // contacts), in the map frame.
  const std::vector<Eigen::Vector3d>& feltGround() const { return felt_; }
  const std::vector<StepRecord>& stepLog() const { return step_log_; }
  const GroundWork& groundWork() const { return work_; }
  // The command round trip (send to acknowledgement, smoothed over the
  // awaited commands); none before the first.
  std::optional<double> roundTripS() const { return round_trip_s_; }
  double ackTimeoutS() const;
  const std::optional<MoveUnderWay>& moveUnderWay() const { return under_way_; }
  // The seconds a command takes the rover by its model: a leg move from
  // the leg's reported joints through its waypoints and down to the
  // lowest reach (contact may come sooner), a body move on its velocity
  // profiles; 0 for anything else.
  double modelledSeconds(const link::CommandBody& command) const;
  // Why the link could not carry the last command, until the rover is
  // heard again; the walk is suspended meanwhile.
  const std::optional<std::string>& linkLost() const { return link_lost_; }
  // Why the walk was last suspended, in a sentence (meaningful while
  // phase() is kSuspended).
  const std::string& suspendedBecause() const { return suspended_because_; }
  // The correction of the rover's dead reckoning in use, and each scan's
  // match against the map, in order.
  const PoseCorrection& correction() const { return corrector_.correction(); }
  const std::vector<ScanMatch>& scanMatches() const { return matches_; }
  // Why the rover last said it holds; empty when it does not.
  const std::string& roverHolding() const { return rover_holding_; }

 private:
  void advance(const std::vector<link::Telemetry>& messages, double now_s);
  // Whether a body move of `body_u` advances the body along the heading:
  // at least one of the planner's body steps.
  bool advancesTheBody(double body_u) const { return body_u >= ctx_.gait.body_step_m; }
  // How far the body moved from `from` to `to` along the walk's heading, in
  // its u (metres; radians in a point turn).
  double advanceAlongHeading(const gait::BodyPose& from, const gait::BodyPose& to) const;
  // Why no step should be proposed after this one, if so.
  std::optional<std::string> noProgress(const gait::StepPlan& next) const;
  void noStepToPropose(double now_s, const std::string& why);
  std::string pointTurnHint() const;
  std::string mapEdgeHint() const;
  void handle(const link::Telemetry& message, double now_s);
  void onAck(const link::CommandAck& ack, double rover_time_s, double now_s);
  // From this acknowledgement on, the move's outcome is awaited, until a limit.
  void expectOutcome(std::uint64_t sequence, double rover_time_s, double now_s);
  std::string outcomeLate() const;
  void onRoverHeartbeat(const link::Heartbeat& heartbeat, double rover_time_s, double now_s);
  void endHold(double now_s);
  void scanAfterResume(double now_s);
  void followMoveWhileSuspended(double now_s);
  void awaitForeignMove(double now_s, const std::string& why);
  void followForeignMove(double now_s);
  void requestScan(double now_s);
  void requestClosingScan(double now_s);
  void acquireScan(int parent_task, const std::string& name, double now_s);
  void scanAgain(double now_s);
  double imageTimeoutS() const;
  void closeWalk(double now_s);
  void mapScan(const sensor::RangeImage& scan, double now_s);
  const ScanMatch& correctPose(const sensor::RangeImage& scan, double now_s);
  // reported_ from the newest report and the correction in use.
  void placeReported();
  gait::StepPlan plan(const gait::Stance& from);
  std::optional<footfall::ScannerView> scannerView(const gait::Stance& from) const;
  void planAndPropose(double now_s);
  void mapDeferredScan(double now_s);
  void planAhead(double now_s);
  std::optional<gait::StepPlan> takeAhead();
  std::optional<StepProposal> checkAhead(gait::StepPlan ahead, double now_s);
  void startExecuting(StepProposal proposal, double now_s);
  void sendNext(double now_s);
  void liftFromWhereItStands(link::LegMove& move) const;
  void afterMove(double now_s);
  void finishStep(double now_s);
  void suspend(double now_s, const std::string& why, bool hold);
  void metOtherGround(double now_s, const Eigen::Vector3d& foot, const std::string& kind,
                      int& in_a_row, int limit, const std::string& what, const std::string& because,
                      const std::string& verdict);
  void feelGround(const Eigen::Vector3d& foot);
  void holdFeltGround(const Eigen::Vector3d& foot);
  void note(double now_s, const std::string& what);
  std::uint64_t send(link::CommandBody body, double now_s);

  link::Link& link_;
  link::CommandSigner& signer_;
  ApprovalGate& gate_;
  gait::GaitContext ctx_;
  ExecutiveOptions opt_;
  terrain::ElevationMap map_;
  std::vector<Eigen::Vector3d> felt_;  // soles that met ground other than the map said
  TaskTree tasks_;
  std::vector<ExecutiveEvent> events_;
  Phase phase_ = Phase::kIdle;
  int steps_done_ = 0, planned_ahead_ = 0;
  int early_contacts_ = 0;  // in a row, since the last step done
  int late_contacts_ = 0;   // likewise
  int steps_without_advance_ = 0;  // in a row, since the last resume
  // The first step of step_log_ whose reported end counts for the advance
  // window: none before the last resume.
  std::size_t window_from_ = 0;
  // The next step, planned during this one from the stance it predicts.
  std::optional<gait::StepPlan> ahead_;
  gait::Stance ahead_from_;
  double ahead_ms_ = 0.0;
  std::vector<StepRecord> step_log_;
  StepRecord step_;                // the step being carried out
  std::string replanned_because_;  // for the step planned again after an early contact
  GroundWork work_;
  std::uint64_t next_proposal_ = 1;
  // Where the rover reports its legs and body; filled by the state
  // telemetry that follows every move.
  RoverReport report_;
  std::optional<gait::Stance> reported_;  // corrected
  PoseCorrector corrector_;
  std::vector<ScanMatch> matches_;
  // The step being carried out: its commands, the next to send, the one
  // awaiting its acknowledgement and since when.
  std::optional<StepProposal> executing_;
  std::size_t next_command_ = 0;
  std::optional<std::uint64_t> awaiting_;
  std::string awaiting_what_;  // its type, for the operator
  double sent_s_ = 0.0;
  std::optional<double> round_trip_s_;
  double last_sent_s_ = -1e300;  // any command, heartbeats included
  bool heard_ = false;           // anything from the rover yet
  std::string rover_holding_;
  std::optional<std::string> link_lost_;  // why the last command could not be sent
  std::string suspended_because_;
  double foreign_move_due_s_ = 0.0;      // console time; awaitForeignMove()
  std::optional<std::uint64_t> resume_;  // a Resume sent, not yet acknowledged
  double resumed_at_s_ = -1e300;         // rover time of the acknowledgement that ended it
  std::optional<MoveUnderWay> under_way_;
  std::optional<sensor::RangeImage> scan_;       // arrived, not yet mapped
  std::optional<sensor::RangeImage> unmapped_;   // its step went out first (planned ahead)
  std::optional<std::size_t> scan_of_step_;      // the logged step the scan asked for ends
  std::uint64_t scan_sequence_ = 0;              // the AcquireScan asked for it
  std::optional<double> scan_acked_s_;           // when the rover acknowledged it
  int scan_attempt_ = 0;                         // AcquireScans sent for this scan
  std::optional<sensor::ScanGeometry> scanner_;  // of the scans mapped so far
  double scan_time_s_ = 0.0;                     // its rover time
  ProductSink product_sink_;
  std::function<void(const sensor::RangeImage&)> scan_sink_;
  std::function<void(const ExecutiveEvent&)> event_sink_;
  int walk_task_ = -1, step_task_ = -1, scan_task_ = -1, plan_task_ = -1, approval_task_ = -1;
  std::vector<int> command_tasks_;
};

}  // namespace ambler::executive
