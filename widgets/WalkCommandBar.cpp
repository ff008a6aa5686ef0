#include "widgets/WalkCommandBar.h"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QSpinBox>

namespace ambler::widgets {

WalkCommandBar::WalkCommandBar(QWidget* parent)
    : QWidget(parent), steps_(new QSpinBox), path_(new QComboBox), radius_(new QDoubleSpinBox) {
  steps_->setRange(1, 1000);
  steps_->setSuffix(tr(" steps"));
  steps_->setToolTip(tr("Steps of the next walk (each a leg move and a body move)"));
  // In the order of WalkCommand::Path.
  path_->addItems({tr("straight"), tr("arc left"), tr("arc right"), tr("turn left in place"),
                   tr("turn right in place")});
  path_->setToolTip(tr("The path the body follows"));
  // Tighter than the tread (2.25 m) the inner stack walks backwards, as in
  // a turn in place.
  radius_->setRange(2.0, 1000.0);
  radius_->setDecimals(1);
  radius_->setSuffix(tr(" m"));
  radius_->setToolTip(tr("Radius of the arc the body's centre follows [m]"));
  auto* layout = new QHBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(steps_);
  layout->addWidget(path_);
  layout->addWidget(new QLabel(tr("radius")));
  layout->addWidget(radius_);
  connect(path_, &QComboBox::currentIndexChanged, this, [this](int index) {
    const auto path = WalkCommand::Path(index);
    radius_->setEnabled(path == WalkCommand::Path::kArcLeft ||
                        path == WalkCommand::Path::kArcRight);
  });
  setCommand({});
}

WalkCommand WalkCommandBar::command() const {
  return {steps_->value(), WalkCommand::Path(path_->currentIndex()), radius_->value()};
}

void WalkCommandBar::setCommand(const WalkCommand& command) {
  steps_->setValue(command.steps);
  radius_->setValue(command.radius_m);
  path_->setCurrentIndex(int(command.path));
  radius_->setEnabled(command.path == WalkCommand::Path::kArcLeft ||
                      command.path == WalkCommand::Path::kArcRight);
}

}  // namespace ambler::widgets
