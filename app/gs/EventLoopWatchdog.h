#pragma once

#include <QElapsedTimer>
#include <QObject>
#include <QTimer>
#include <array>

namespace ambler::gs {

// How the GUI thread's event loop kept up, in milliseconds: each stall is
// how much later than due a tick of a short timer came.
struct StallSummary {
  long ticks = 0;
  double p50_ms = 0.0, p99_ms = 0.0, max_ms = 0.0;
  long over_20ms = 0, over_50ms = 0;  // ticks late by 20 ms or more, by 50 ms or more
  double worst_at_s = 0.0;            // since start(), when the longest stall ended
};

// A timer on the thread it lives on (the GUI thread) that ticks every
// `period_ms`; a tick that comes late measures a stall of the event loop:
// work that kept the operator's clicks and repaints waiting. Quantiles are
// the upper edge of their histogram bin (0.1 ms below 100 ms).
class EventLoopWatchdog : public QObject {
  Q_OBJECT

 public:
  explicit EventLoopWatchdog(int period_ms = 5, QObject* parent = nullptr);

  void start();  // forgets what was measured before
  void stop();
  void resume();  // after stop(), keeping what was measured; the pause is not a stall
  [[nodiscard]] StallSummary summary() const;

 private:
  void tick();

  int period_ms_;
  QTimer timer_;
  QElapsedTimer clock_;
  qint64 last_ns_ = 0;
  // A histogram, so that it can run for a whole shift in fixed memory:
  // 0.1 ms bins up to 100 ms, 10 ms bins up to 10 s, one bin beyond.
  static constexpr int kFine = 1000, kCoarse = 990;
  std::array<long, kFine + kCoarse + 1> bins_{};
  long ticks_ = 0;
  double worst_ms_ = 0.0, worst_at_s_ = 0.0;
};

}  // namespace ambler::gs
