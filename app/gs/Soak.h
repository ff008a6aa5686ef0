#pragma once

#include <QElapsedTimer>
#include <QObject>
#include <QTimer>
#include <vector>

#include "app/gs/EventLoopWatchdog.h"
#include "app/gs/GroundStation.h"

namespace ambler::gs {

// A shift, accelerated (ambler-gs --soak N): auto-approved walks of up to
// 50 steps on courses 1-10 in turn (a walk ends done, suspended, or on a
// step whose interlocks fail, which waits for an operator even on
// auto-approve), each followed by opening its log,
// scrubbing the replay and going through the tabs, until N steps are
// walked; resident memory is read after each walk (the growth is counted
// from the walk that passes 200 steps to the end). Prints JSON and quits.
class Soak : public QObject {
  Q_OBJECT

 public:
  Soak(GroundStation& station, EventLoopWatchdog& watchdog, int steps);

 private:
  void startWalk();
  void poll();
  void replay();
  void finish();

  GroundStation& station_;
  EventLoopWatchdog& watchdog_;
  int target_steps_;
  int steps_ = 0, walks_ = 0, held_ = 0;  // held: ended on a step waiting for an operator
  double rss_at_200_mb_ = -1.0;
  std::vector<double> rss_after_walk_mb_;  // whether it levels off or keeps growing
  QTimer poll_;
  QElapsedTimer clock_;
  bool started_ = false;
};

// Resident memory of this process [MB], from /proc/self/statm.
double residentMb();

}  // namespace ambler::gs
