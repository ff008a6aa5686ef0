#include "widgets/TimelineBar.h"

#include <QComboBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QSlider>
#include <QStyle>
#include <QToolButton>
#include <algorithm>
#include <cmath>

namespace ambler::widgets {

namespace {
constexpr int kSliderSteps = 10000;  // 0.01 % of the mission per step
}

TimelineBar::TimelineBar(QWidget* parent)
    : QWidget(parent),
      back_(new QToolButton),
      play_(new QToolButton),
      forward_(new QToolButton),
      slider_(new QSlider(Qt::Horizontal)),
      speed_(new QComboBox),
      label_(new QLabel) {
  back_->setIcon(style()->standardIcon(QStyle::SP_MediaSkipBackward));
  back_->setToolTip(tr("Back to the previous scan, decision or answer"));
  play_->setIcon(style()->standardIcon(QStyle::SP_MediaPlay));
  play_->setToolTip(tr("Play / pause (Space)"));
  play_->setShortcut(Qt::Key_Space);
  forward_->setIcon(style()->standardIcon(QStyle::SP_MediaSkipForward));
  forward_->setToolTip(tr("On to the next scan, decision or answer"));
  slider_->setRange(0, kSliderSteps);
  slider_->setToolTip(tr("Drag to scrub through the mission"));
  for (double s : {0.5, 1.0, 2.0, 5.0, 10.0}) speed_->addItem(tr("%1x").arg(s), s);
  speed_->setCurrentIndex(1);
  speed_->setToolTip(tr("Playback speed"));
  label_->setMinimumWidth(170);
  slider_->setMinimumWidth(300);
  setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Preferred);  // the toolbar's whole width
  auto* row = new QHBoxLayout(this);
  row->setContentsMargins(4, 2, 4, 2);
  for (QWidget* w : std::initializer_list<QWidget*>{back_, play_, forward_}) row->addWidget(w);
  row->addWidget(slider_, 1);
  row->addWidget(speed_);
  row->addWidget(label_);

  connect(back_, &QToolButton::clicked, this, &TimelineBar::stepBack);
  connect(forward_, &QToolButton::clicked, this, &TimelineBar::stepForward);
  connect(play_, &QToolButton::clicked, this, [this] { playing() ? pause() : play(); });
  // Only the operator moves the slider: showTime() sets it with signals blocked.
  connect(slider_, &QSlider::valueChanged, this,
          [this](int v) { setTime(first_s_ + (last_s_ - first_s_) * v / kSliderSteps); });
  connect(&timer_, &QTimer::timeout, this, &TimelineBar::advance);
  setEnabled(false);
  showTime();
}

void TimelineBar::setRange(double first_s, double last_s, std::vector<double> marks) {
  pause();
  first_s_ = first_s, last_s_ = std::max(first_s, last_s), marks_ = std::move(marks);
  std::sort(marks_.begin(), marks_.end());
  setEnabled(true);
  time_s_ = first_s_ - 1.0;  // so that the next line moves and tells
  setTime(first_s_);
}

void TimelineBar::setTime(double time_s) {
  time_s = std::clamp(time_s, first_s_, last_s_);
  if (time_s == time_s_) return;
  time_s_ = time_s;
  showTime();
  emit timeChanged(time_s_);
}

void TimelineBar::showTime() {
  const QSignalBlocker block(slider_);
  const double span = std::max(last_s_ - first_s_, 1e-9);
  slider_->setValue(int(std::lround((time_s_ - first_s_) / span * kSliderSteps)));
  label_->setText(
      tr("t = %1 s of %2 s").arg(time_s_ - first_s_, 0, 'f', 1).arg(last_s_ - first_s_, 0, 'f', 1));
}

void TimelineBar::stepForward() {
  pause();
  const auto next = std::upper_bound(marks_.begin(), marks_.end(), time_s_);
  setTime(next == marks_.end() ? last_s_ : *next);
}

void TimelineBar::stepBack() {
  pause();
  const auto previous = std::lower_bound(marks_.begin(), marks_.end(), time_s_);
  setTime(previous == marks_.begin() ? first_s_ : *std::prev(previous));
}

void TimelineBar::play() {
  if (time_s_ >= last_s_) setTime(first_s_);
  since_tick_.start();
  timer_.start(50);
  play_->setIcon(style()->standardIcon(QStyle::SP_MediaPause));
}

void TimelineBar::pause() {
  timer_.stop();
  play_->setIcon(style()->standardIcon(QStyle::SP_MediaPlay));
}

void TimelineBar::advance() {
  const double speed = speed_->currentData().toDouble();
  setTime(time_s_ + speed * since_tick_.restart() / 1000.0);
  if (time_s_ >= last_s_) pause();
}

}  // namespace ambler::widgets
