#pragma once

#include <QObject>
#include <QTimer>
#include <memory>

#include "executive/WalkExecutive.h"
#include "walk/AutonomousWalk.h"

namespace ambler::gs {

// One walk as the GUI runs it: a link to a rover (the simulator in this
// process by default), the executive and its approval gate, polled on the
// GUI thread. The views read its state when changed() is emitted; the
// operator's decisions come in through approve() and reject().
class WalkSession : public QObject {
  Q_OBJECT

 public:
  // The built-in simulator on course `seed`, commanded by `operator_id`
  // with a key made for this session.
  WalkSession(const walk::WalkConfig& config, std::uint64_t seed, const QString& operator_id,
              QObject* parent = nullptr);
  ~WalkSession() override;

  void start(int steps);
  QString approve(quint64 proposal);  // empty when done, else why not
  QString reject(quint64 proposal, const QString& reason);
  // The operator moved the pending step's foothold: replanned, interlocks
  // checked again, still pending.
  QString editFoothold(quint64 proposal, double x_m, double y_m);
  void setAutoApprove(bool on);

  const executive::WalkExecutive& executive() const { return *executive_; }
  const std::optional<executive::StepProposal>& pending() const { return gate_.pending(); }
  QString linkDescription() const;
  // Seconds since the rover's last message; none before the first.
  std::optional<double> linkAgeS() const;

 signals:
  void changed();

 private:
  void poll();
  double nowS() const;

  gait::GaitContext context_;
  std::unique_ptr<link::Link> rover_;
  link::LinkHealth health_;
  std::unique_ptr<link::Link> link_;  // rover_, watched for health_
  std::unique_ptr<link::CommandSigner> signer_;
  executive::ApprovalGate gate_;
  std::unique_ptr<executive::WalkExecutive> executive_;
  QTimer timer_;
  QString operator_id_;
  std::optional<quint64> last_pending_;
  executive::Phase last_phase_ = executive::Phase::kIdle;
};

}  // namespace ambler::gs
