#include "app/gs/Soak.h"

#include <cmath>

#include <unistd.h>

#include <QApplication>
#include <QCheckBox>
#include <QTabWidget>
#include <fstream>
#include <iostream>

#include "widgets/StepApprovalPanel.h"
#include "widgets/TimelineBar.h"

namespace ambler::gs {

double residentMb() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return double(resident) * double(::sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

Soak::Soak(GroundStation& station, EventLoopWatchdog& watchdog, int steps)
    : station_(station), watchdog_(watchdog), target_steps_(steps) {
  auto& window = station_.window();
  connect(&window, &widgets::MainWindow::scanShown, this, [this] {
    if (std::exchange(started_, true)) return;
    clock_.start();
    watchdog_.start();
    station_.window().approvalPanel()->autoApproveSwitch()->setChecked(true);
    startWalk();
  });
  connect(&station_, &GroundStation::replayReady, this, &Soak::replay);
  connect(&station_, &GroundStation::replayFailed, this, [this] { startWalk(); });
  connect(&poll_, &QTimer::timeout, this, &Soak::poll);
}

void Soak::startWalk() {
  widgets::ConnectChoice course;
  course.seed = 1 + quint64(walks_ % 10);
  if (station_.connectTo(course).refused()) return finish();
  ++walks_;
  station_.startWalk(std::min(50, target_steps_ - steps_));
  poll_.start(200);
}

void Soak::poll() {
  const auto* session = station_.session();
  if (!session) return;
  const auto& state = session->state();
  // A step whose interlocks fail waits for an operator even on
  // auto-approve; unattended, that ends the walk as a suspension would.
  const bool held = state.pending && !state.pending->interlocks.passed();
  if (state.phase != executive::Phase::kDone && state.phase != executive::Phase::kSuspended &&
      !held)
    return;
  held_ += held;
  poll_.stop();
  const int walked = state.steps_done;
  rss_after_walk_mb_.push_back(residentMb());
  if (steps_ < 200 && steps_ + walked >= 200) rss_at_200_mb_ = rss_after_walk_mb_.back();
  steps_ += walked;
  if (steps_ >= target_steps_ || walked == 0) return finish();
  station_.openLog(QString::fromStdString(session->logPath().string()));
}

// The replay scrubbed end to end and every tab looked at, as an operator
// reviewing the walk would.
void Soak::replay() {
  const auto* timeline = station_.timeline();
  auto* bar = station_.window().timeline();
  for (int i = 0; i <= 10; ++i) {
    bar->setTime(timeline->firstS() + (timeline->lastS() - timeline->firstS()) * i / 10.0);
    QApplication::processEvents();
  }
  if (auto* tabs = station_.window().findChild<QTabWidget*>())
    for (int i = 0; i < tabs->count(); ++i) {
      tabs->setCurrentIndex(i);
      QApplication::processEvents();
    }
  QTimer::singleShot(0, this, &Soak::startWalk);
}

void Soak::finish() {
  poll_.stop();
  watchdog_.stop();
  const double end_mb = residentMb();
  std::cout << "{\"steps\": " << steps_ << ", \"walks\": " << walks_
            << ", \"walks_held_for_an_operator\": " << held_
            << ", \"wall_s\": " << double(clock_.elapsed()) / 1000.0
            << ", \"rss_mb_at_200_steps\": " << rss_at_200_mb_ << ", \"rss_mb_end\": " << end_mb
            << ", \"rss_growth_after_200_steps_mb\": "
            << (rss_at_200_mb_ >= 0 ? end_mb - rss_at_200_mb_ : 0.0)
            << ", \"stall_p99_ms\": " << watchdog_.summary().p99_ms
            << ", \"stall_max_ms\": " << watchdog_.summary().max_ms
            << ", \"rss_mb_after_each_walk\": [";
  for (std::size_t i = 0; i < rss_after_walk_mb_.size(); ++i)
    std::cout << (i ? ", " : "") << std::lround(rss_after_walk_mb_[i]);
  std::cout << "]}" << std::endl;
  QApplication::exit(0);
}

}  // namespace ambler::gs
