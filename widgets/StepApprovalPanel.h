#pragma once

#include <QWidget>
#include <optional>

#include "executive/ApprovalGate.h"

class QCheckBox;
class QLabel;
class QPushButton;
class QTableWidget;

namespace ambler::widgets {

// The step waiting for the operator: leg, foothold, body advance,
// stability margin and every interlock with its figures, with Approve and
// Reject and the auto-approve switch, which turns the panel's banner red
// while it is on; above them what the walk is doing and, when it stopped,
// why, with Resume. It shows what it is given and says what the operator
// decided; the executive does the rest.
class StepApprovalPanel : public QWidget {
  Q_OBJECT

 public:
  explicit StepApprovalPanel(QWidget* parent = nullptr);

  // Nothing: no step is waiting; the buttons are disabled.
  void showProposal(const std::optional<executive::StepProposal>& proposal);
  // What the walk is doing ("awaiting decision", "suspended", ...) and, when
  // it has stopped, why, in a sentence; `alarm` shows it in red.
  void setPhase(const QString& phase, const QString& why = {}, bool alarm = false);
  // Whether Resume can restart a stopped walk.
  void setResumable(bool on);
  void setAutoApprove(bool on);
  // A replay decides nothing: the banner says so instead of the live mode.
  void setReplay(bool on);

  QPushButton* approveButton() const { return approve_; }
  QPushButton* rejectButton() const { return reject_; }
  QPushButton* resumeButton() const { return resume_; }
  QLabel* phaseLabel() const { return phase_; }
  QLabel* reasonLabel() const { return why_; }
  QCheckBox* autoApproveSwitch() const { return auto_approve_; }
  QTableWidget* interlockTable() const { return interlocks_; }
  QLabel* banner() const { return banner_; }

 signals:
  void approveRequested(quint64 proposal);
  void rejectRequested(quint64 proposal);
  void resumeRequested();
  void autoApproveChanged(bool on);

 private:
  void showMode();

  std::optional<quint64> shown_;
  bool replay_ = false;
  QLabel* banner_;
  QLabel* phase_;
  QLabel* why_;
  QLabel* summary_;
  QTableWidget* interlocks_;
  QPushButton* approve_;
  QPushButton* reject_;
  QPushButton* resume_;
  QCheckBox* auto_approve_;
};

}  // namespace ambler::widgets
