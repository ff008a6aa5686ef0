#pragma once

#include <QObject>
#include <QString>
#include <QThread>
#include <filesystem>
#include <functional>
#include <memory>

#include "app/gs/WalkState.h"
#include "executive/WalkExecutive.h"
#include "link/Signing.h"
#include "rover/SimulatedGround.h"
#include "rover/SimulatedRover.h"
#include "sampling/GraspPlan.h"

namespace ambler::gs {

// A rover to walk: the link to it, this operator's key, and what the log
// calls the mission.
struct RoverConnection {
  // Opens the link, on the session's thread: the built-in simulator builds
  // its course there, which takes a third of a second.
  std::function<std::unique_ptr<link::Link>()> open;
  std::string description;  // the link, for the status bar
  link::OperatorKey key;
  std::uint32_t rover_id = 1;
  std::uint64_t first_sequence = 1;  // missionlog::firstSequenceFromClock() for a real rover
  std::string mission;
};

// The built-in simulator on `ground` drawn from `seed` (a terrain model's
// seed draws only the noise), commanded by `operator_id` with a key made
// for this session.
RoverConnection simulatorConnection(const rover::SimulatedRoverConfig& config, std::uint64_t seed,
                                    const QString& operator_id,
                                    const rover::SimulatedGround& ground = {});

// What the operator asked for that may be refused.
enum class OperatorAction {
  kConnect,
  kApprove,
  kReject,
  kEditFoothold,
  kAutoApprove,
  kGrasp,
  kAuthority
};

class WalkWorker;

// One walk as the GUI runs it: a link to a rover (the simulator in this
// process by default), the executive and its approval gate. They live on
// the session's own thread, where the executive is polled and maps and
// plans; the GUI thread only asks (approve, hold, ...) and is told, by
// queued calls: each change of the walk arrives as a whole WalkState, and
// changed() is emitted. Everything sent and received, every decision and
// every map goes to a mission log first (nothing is lost if the station
// dies).
class WalkSession : public QObject {
  Q_OBJECT

 public:
  // Recorded in the log at `log_path` (created, or appended to, on the
  // session's thread; refused() with OperatorAction::kConnect when it
  // cannot be).
  WalkSession(const gait::GaitContext& context, RoverConnection rover,
              const std::filesystem::path& log_path, QObject* parent = nullptr);
  // Waits for the step the session's thread is working on, then ends it.
  ~WalkSession() override;

  // Each of these is carried out on the session's thread; a refusal comes
  // back as refused().
  void start(int steps, const gait::Heading& heading = {});
  void approve(quint64 proposal);
  void reject(quint64 proposal, const QString& reason);
  // The operator moved the pending step's foothold: replanned, interlocks
  // checked again, still pending.
  void editFoothold(quint64 proposal, double x_m, double y_m);
  void setAutoApprove(bool on);
  // The operator's Hold: sent signed as soon as the session's thread is
  // free (WalkExecutive::hold).
  void hold();
  // After a stop (a hold, a rejection, a suspension): the rover's hold is
  // ended and the walk scans and plans again (WalkExecutive::resume).
  void resume();
  // The operator approved this grasp (`detail`: JSON of the fit behind it):
  // checked against the rover's limits, logged, signed and sent (then
  // graspSent()). Refused while a walk is under way.
  void sendGrasp(const sampling::GraspPlan& plan, const std::string& detail);
  // Command authority (link::CommandAuthority): ask for it; or, holding
  // it, hand it to the console asking, between two steps only.
  void requestAuthority();
  void handOver();

  // The walk as last told; a state with nothing in it before the first.
  const WalkState& state() const { return *state_; }
  const std::shared_ptr<const WalkState>& sharedState() const { return state_; }
  const std::optional<executive::StepProposal>& pending() const { return state_->pending; }
  const std::vector<replay::LogRow>& commandRows() const { return *state_->rows; }
  const std::filesystem::path& logPath() const { return log_path_; }
  QString linkDescription() const { return QString::fromStdString(link_description_); }
  // Seconds since the rover's last message; none before the first.
  std::optional<double> linkAgeS() const;

 signals:
  void changed();
  // A scan the executive has mapped (dead-reckoned pose).
  void scanMapped(const ambler::sensor::RangeImage& scan);
  // An event of the walk, in a sentence (also logged and in the table).
  void eventNoted(const QString& what);
  void refused(ambler::gs::OperatorAction action, const QString& why);
  void graspSent();
  // The rover answered the last grasp sent: accepted, or refused and why.
  void graspAnswered(bool accepted, const QString& reason);

 private:
  friend class WalkWorker;  // tells the session by queued calls only
  void take(std::shared_ptr<const WalkState> state);
  template <typename F>
  void ask(F f);

  std::filesystem::path log_path_;
  std::string link_description_;
  std::string operator_id_;
  std::shared_ptr<const WalkState> state_ = std::make_shared<const WalkState>();
  QThread thread_;
  WalkWorker* worker_ = nullptr;  // lives on thread_, deleted there
};

}  // namespace ambler::gs
