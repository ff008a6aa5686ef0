#pragma once

#include <QElapsedTimer>
#include <QTimer>
#include <QWidget>
#include <vector>

class QComboBox;
class QLabel;
class QSlider;
class QToolButton;

namespace ambler::widgets {

// The replay's timeline: play / pause at a chosen speed, step to
// the previous or next mark (a scan, a decision, an answer), and a slider
// to scrub. Times are seconds on the log's clock; the label shows them
// from the start of the mission.
class TimelineBar : public QWidget {
  Q_OBJECT

 public:
  explicit TimelineBar(QWidget* parent = nullptr);

  void setRange(double first_s, double last_s, std::vector<double> marks);
  double time() const { return time_s_; }
  void setTime(double time_s);  // clamped; emits timeChanged when it moves
  void stepForward();
  void stepBack();
  void play();
  void pause();
  bool playing() const { return timer_.isActive(); }

  QSlider* slider() const { return slider_; }
  QLabel* label() const { return label_; }

 signals:
  void timeChanged(double time_s);

 private:
  void advance();
  void showTime();

  double first_s_ = 0.0, last_s_ = 0.0, time_s_ = 0.0;
  std::vector<double> marks_;
  QToolButton* back_;
  QToolButton* play_;
  QToolButton* forward_;
  QSlider* slider_;
  QComboBox* speed_;
  QLabel* label_;
  QTimer timer_;
  QElapsedTimer since_tick_;
};

}  // namespace ambler::widgets
