#include "widgets/StepApprovalPanel.h"

#include <QCheckBox>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QPushButton>
#include <QTableWidget>
#include <QVBoxLayout>

namespace ambler::widgets {

namespace {

QString describeStep(const executive::StepProposal& p) {
  const auto& plan = p.plan;
  QString text = QObject::tr("<b>Step %1</b><br>").arg(p.id);
  if (plan.leg >= 0)
    text += QObject::tr("Leg %1 to foothold (%2, %3, %4) m<br>")
                .arg(plan.leg)
                .arg(plan.foothold.x(), 0, 'f', 2)
                .arg(plan.foothold.y(), 0, 'f', 2)
                .arg(plan.foothold.z(), 0, 'f', 2);
  else
    text += QObject::tr("Body move only, no leg lifted<br>");
  text += QObject::tr("Body moves %1 m and turns %2°<br>Least stability margin %3 m")
              .arg(p.body_move_m, 0, 'f', 3)
              .arg(p.body_turn_deg, 0, 'f', 1)
              .arg(plan.min_csp_margin, 0, 'f', 3);
  return text;
}

}  // namespace

StepApprovalPanel::StepApprovalPanel(QWidget* parent)
    : QWidget(parent),
      banner_(new QLabel(this)),
      phase_(new QLabel(this)),
      why_(new QLabel(this)),
      summary_(new QLabel(this)),
      interlocks_(new QTableWidget(0, 3, this)),
      approve_(new QPushButton(tr("&Approve"), this)),
      reject_(new QPushButton(tr("&Reject"), this)),
      resume_(new QPushButton(tr("Re&sume walk"), this)),
      auto_approve_(new QCheckBox(tr("Auto-appro&ve steps that pass every interlock"), this)) {
  banner_->setAlignment(Qt::AlignCenter);
  banner_->setMargin(4);
  // Wrapped, so that no text widens the dock under the operator's hand.
  banner_->setWordWrap(true);
  phase_->setWordWrap(true);
  why_->setWordWrap(true);
  // Room for a two-line reason kept whether or not there is one, so that
  // nothing below moves when a walk stops.
  why_->setMinimumHeight(2 * why_->fontMetrics().lineSpacing());
  why_->setAlignment(Qt::AlignTop | Qt::AlignLeft);
  why_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  summary_->setWordWrap(true);
  auto_approve_->setToolTip(auto_approve_->text().remove('&'));
  summary_->setTextFormat(Qt::RichText);
  interlocks_->setHorizontalHeaderLabels({tr("Interlock"), tr("Result"), tr("Figures")});
  interlocks_->horizontalHeader()->setSectionResizeMode(0, QHeaderView::ResizeToContents);
  interlocks_->horizontalHeader()->setSectionResizeMode(1, QHeaderView::ResizeToContents);
  interlocks_->horizontalHeader()->setSectionResizeMode(2, QHeaderView::Stretch);
  interlocks_->setWordWrap(true);
  interlocks_->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  interlocks_->verticalHeader()->hide();
  interlocks_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  interlocks_->setMinimumHeight(230);  // five checks with two lines of figures each
  approve_->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_Return));
  reject_->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_Backspace));
  approve_->setToolTip(tr("Send the step's moves to the rover (Ctrl+Return)"));
  reject_->setToolTip(tr("Send nothing; the walk is suspended (Ctrl+Backspace)"));
  resume_->setToolTip(
      tr("End the rover's hold, scan again and plan the next step afresh from where it stands"));

  auto* buttons = new QHBoxLayout;
  buttons->addWidget(approve_);
  buttons->addWidget(reject_);
  auto* layout = new QVBoxLayout(this);
  layout->addWidget(banner_);
  auto* walk = new QHBoxLayout;
  walk->addWidget(phase_, 1);
  walk->addWidget(resume_);
  layout->addLayout(walk);
  layout->addWidget(why_);
  layout->addWidget(summary_);
  layout->addWidget(interlocks_, 1);
  layout->addLayout(buttons);
  layout->addWidget(auto_approve_);

  connect(approve_, &QPushButton::clicked, this, [this] {
    if (shown_) emit approveRequested(*shown_);
  });
  connect(reject_, &QPushButton::clicked, this, [this] {
    if (shown_) emit rejectRequested(*shown_);
  });
  connect(resume_, &QPushButton::clicked, this, &StepApprovalPanel::resumeRequested);
  connect(auto_approve_, &QCheckBox::toggled, this, [this](bool on) {
    setAutoApprove(on);
    emit autoApproveChanged(on);
  });
  setAutoApprove(false);
  setPhase(tr("idle"));
  setResumable(false);
  showProposal(std::nullopt);
}

void StepApprovalPanel::setAutoApprove(bool on) {
  if (auto_approve_->isChecked() != on) auto_approve_->setChecked(on);
  showMode();
}

void StepApprovalPanel::setReplay(bool on) {
  replay_ = on;
  showMode();
}

void StepApprovalPanel::showMode() {
  if (replay_) {
    banner_->setText(tr("Replay: the decisions the log holds; nothing is sent"));
    banner_->setStyleSheet("background:#546e7a;color:white");
    return;
  }
  // Visible from across the room: nobody is asked before the rover moves.
  const bool on = auto_approve_->isChecked();
  banner_->setText(on ? tr("AUTO-APPROVE ON: steps that pass every interlock are sent")
                      : tr("Operator approval: every step waits for you"));
  banner_->setStyleSheet(on ? "background:#b71c1c;color:white;font-weight:bold"
                            : "background:#2e7d32;color:white");
}

void StepApprovalPanel::setPhase(const QString& phase, const QString& why, bool alarm) {
  phase_->setText(tr("Walk: <b>%1</b>").arg(phase.toHtmlEscaped()));
  why_->setText(why.isEmpty() ? why : why.front().toUpper() + why.mid(1));
  why_->setStyleSheet(alarm ? "color:#b71c1c;font-weight:bold" : "");
}

void StepApprovalPanel::setResumable(bool on) { resume_->setEnabled(on); }

void StepApprovalPanel::showProposal(const std::optional<executive::StepProposal>& proposal) {
  shown_.reset();
  interlocks_->setRowCount(0);
  if (!proposal) {
    summary_->setText(tr("No step is waiting for a decision."));
    approve_->setEnabled(false);
    reject_->setEnabled(false);
    return;
  }
  shown_ = proposal->id;
  summary_->setText(describeStep(*proposal));
  for (const auto& check : proposal->interlocks.checks) {
    const int row = interlocks_->rowCount();
    interlocks_->insertRow(row);
    interlocks_->setItem(row, 0, new QTableWidgetItem(QString::fromStdString(check.name)));
    auto* result = new QTableWidgetItem(check.passed ? tr("passed") : tr("FAILED"));
    result->setForeground(check.passed ? QColor("#2e7d32") : QColor("#b71c1c"));
    interlocks_->setItem(row, 1, result);
    auto* figures = new QTableWidgetItem(QString::fromStdString(check.detail));
    figures->setToolTip(figures->text());
    interlocks_->setItem(row, 2, figures);
  }
  interlocks_->resizeRowsToContents();
  // A step that fails an interlock cannot be approved by anyone.
  approve_->setEnabled(proposal->interlocks.passed());
  reject_->setEnabled(true);
}

}  // namespace ambler::widgets
