#include "widgets/WalkCommandBar.h"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QSpinBox>

namespace ambler::widgets {

namespace {

bool isArc(WalkCommand::Path path) {
  return path == WalkCommand::Path::kArcLeft || path == WalkCommand::Path::kArcRight;
}

}  // namespace

WalkCommandBar::WalkCommandBar(QWidget* parent)
    : QWidget(parent), steps_(new QSpinBox), path_(new QComboBox), radius_(new QDoubleSpinBox) {
  steps_->setRange(1, 1000);
  steps_->setSuffix(tr(" steps"));
  connect(steps_, &QSpinBox::valueChanged, this,
          [this](int n) { steps_->setSuffix(n == 1 ? tr(" step") : tr(" steps")); });
  steps_->setToolTip(tr("Steps of the next walk (each a leg move and a body move)"));
  // In the order of WalkCommand::Path.
  path_->addItems({tr("straight"), tr("arc left"), tr("arc right"), tr("turn left in place"),
                   tr("turn right in place")});
  path_->setToolTip(tr("The path the body follows"));
  // From 2 m: a tighter arc turns nearly in place (the stacks stand 4.5 m
  // apart), which the path list offers as such.
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
  connect(path_, &QComboBox::currentIndexChanged, this,
          [this](int index) { radius_->setEnabled(isArc(WalkCommand::Path(index))); });
  setCommand({});
}

WalkCommand WalkCommandBar::command() const {
  return {steps_->value(), WalkCommand::Path(path_->currentIndex()), radius_->value()};
}

void WalkCommandBar::setCommand(const WalkCommand& command) {
  steps_->setValue(command.steps);
  radius_->setValue(command.radius_m);
  path_->setCurrentIndex(int(command.path));
  radius_->setEnabled(isArc(command.path));
}

}  // namespace ambler::widgets
