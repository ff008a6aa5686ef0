#pragma once

#include <QObject>
#include <QTimer>
#include <memory>

#include <filesystem>

#include "core/Refusal.h"
#include "executive/WalkExecutive.h"
#include "missionlog/ReplayLinks.h"
#include "replay/CommandTable.h"
#include "rover/SimulatedRover.h"
#include "sampling/GraspPlan.h"

namespace ambler::gs {

// A rover to walk: the link to it, this operator's key, and what the log
// calls the mission.
struct RoverConnection {
  std::unique_ptr<link::Link> link;
  link::OperatorKey key;
  std::uint32_t rover_id = 1;
  std::uint64_t first_sequence = 1;  // missionlog::firstSequenceFromClock() for a real rover
  std::string mission;
};

// The built-in simulator on course `seed`, commanded by `operator_id` with
// a key made for this session.
RoverConnection simulatorConnection(const rover::SimulatedRoverConfig& config, std::uint64_t seed,
                                    const QString& operator_id);

// One walk as the GUI runs it: a link to a rover (the simulator in this
// process by default), the executive and its approval gate, polled on the
// GUI thread. Everything sent and received, every decision and every map
// goes to a mission log first (nothing is lost if the station dies). The
// views read its state when changed() is emitted; the operator's decisions
// come in through approve() and reject().
class WalkSession : public QObject {
  Q_OBJECT

 public:
  // Recorded in the log at `log_path` (created, or appended to;
  // missionlog::LogError when it cannot be).
  WalkSession(const gait::GaitContext& context, RoverConnection rover,
              const std::filesystem::path& log_path, QObject* parent = nullptr);
  ~WalkSession() override;

  void start(int steps);
  Refusal approve(quint64 proposal);
  Refusal reject(quint64 proposal, const QString& reason);
  // The operator moved the pending step's foothold: replanned, interlocks
  // checked again, still pending.
  Refusal editFoothold(quint64 proposal, double x_m, double y_m);
  void setAutoApprove(bool on);
  // The operator's Hold: sent signed at once (WalkExecutive::hold).
  void hold();
  // After a stop (a hold, a rejection, a suspension): the rover's hold is
  // ended and the walk scans and plans again (WalkExecutive::resume).
  void resume();
  // The operator approved this grasp (`detail`: JSON of the fit behind it):
  // checked against the rover's limits, logged, signed and sent. Refused
  // while a walk is under way.
  Refusal sendGrasp(const sampling::GraspPlan& plan, const std::string& detail);

  const executive::WalkExecutive& executive() const { return *executive_; }
  const std::optional<executive::StepProposal>& pending() const { return gate_.pending(); }
  const std::vector<replay::LogRow>& commandRows() const { return table_.rows(); }
  const std::filesystem::path& logPath() const { return log_path_; }
  QString linkDescription() const;
  // Seconds since the rover's last message; none before the first.
  std::optional<double> linkAgeS() const;

 signals:
  void changed();
  // A scan the executive has mapped (dead-reckoned pose); same thread.
  void scanMapped(const ambler::sensor::RangeImage& scan);
  // An event of the walk, in a sentence (also logged and in the table).
  void eventNoted(const QString& what);
  // The rover answered the last grasp sent: accepted, or refused and why.
  void graspAnswered(bool accepted, const QString& reason);

 private:
  void poll();
  void answerGrasp();
  void makeExecutive(const executive::ExecutiveOptions& options);
  double nowS() const;

  gait::GaitContext context_;
  std::filesystem::path log_path_;
  missionlog::MissionLog log_;
  replay::CommandTable table_;
  RoverConnection rover_;
  std::unique_ptr<link::Link> recording_;  // rover_.link, to log_
  link::LinkHealth health_;
  std::unique_ptr<link::Link> link_;  // recording_, watched for health_ and table_
  std::unique_ptr<link::CommandSigner> signer_;
  executive::ApprovalGate gate_;
  std::unique_ptr<executive::WalkExecutive> executive_;
  QTimer timer_;
  QString operator_id_;
  std::optional<std::size_t> grasp_row_;  // the last grasp's row, until answered
  std::optional<quint64> last_pending_;
  std::size_t last_rows_ = 0;
  executive::Phase last_phase_ = executive::Phase::kIdle;
};

}  // namespace ambler::gs
