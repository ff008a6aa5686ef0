#include "app/gs/EventLoopWatchdog.h"

#include <algorithm>
#include <cstddef>

namespace ambler::gs {

EventLoopWatchdog::EventLoopWatchdog(int period_ms, QObject* parent)
    : QObject(parent), period_ms_(period_ms) {
  timer_.setTimerType(Qt::PreciseTimer);
  timer_.setInterval(period_ms_);
  connect(&timer_, &QTimer::timeout, this, &EventLoopWatchdog::tick);
}

namespace {

constexpr double kFineMs = 0.1, kCoarseMs = 10.0;

}  // namespace

void EventLoopWatchdog::start() {
  bins_.fill(0);
  ticks_ = 0;
  worst_ms_ = worst_at_s_ = 0.0;
  clock_.start();
  last_ns_ = 0;
  timer_.start();
}

void EventLoopWatchdog::stop() { timer_.stop(); }

void EventLoopWatchdog::resume() {
  last_ns_ = clock_.nsecsElapsed();
  timer_.start();
}

void EventLoopWatchdog::tick() {
  const qint64 now_ns = clock_.nsecsElapsed();
  const double late_ms = std::max(0.0, double(now_ns - last_ns_) / 1e6 - period_ms_);
  last_ns_ = now_ns;
  const int bin =
      late_ms < kFine * kFineMs
          ? int(late_ms / kFineMs)
          : std::min(kFine + kCoarse, kFine + int((late_ms - kFine * kFineMs) / kCoarseMs));
  ++bins_[std::size_t(bin)];
  ++ticks_;
  if (late_ms > worst_ms_) worst_ms_ = late_ms, worst_at_s_ = double(now_ns) / 1e9;
}

StallSummary EventLoopWatchdog::summary() const {
  StallSummary s;
  s.ticks = ticks_;
  if (ticks_ == 0) return s;
  const auto upper_edge = [](int bin) {
    return bin < kFine ? (bin + 1) * kFineMs : kFine * kFineMs + (bin - kFine + 1) * kCoarseMs;
  };
  const auto quantile = [&](double q) {
    const long rank = long(q * double(ticks_ - 1));
    long seen = 0;
    for (int bin = 0; bin < int(bins_.size()); ++bin)
      if ((seen += bins_[std::size_t(bin)]) > rank) return std::min(upper_edge(bin), worst_ms_);
    return worst_ms_;
  };
  s.p50_ms = quantile(0.50);
  s.p99_ms = quantile(0.99);
  s.max_ms = worst_ms_;
  // Bins 200 and 500 start at 20 ms and 50 ms.
  for (int bin = 0; bin < int(bins_.size()); ++bin) {
    s.over_20ms += bin >= 200 ? bins_[std::size_t(bin)] : 0;
    s.over_50ms += bin >= 500 ? bins_[std::size_t(bin)] : 0;
  }
  s.worst_at_s = worst_at_s_;
  return s;
}

}  // namespace ambler::gs
