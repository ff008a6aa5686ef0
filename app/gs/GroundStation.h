#pragma once

#include <QFutureWatcher>
#include <QObject>
#include <QProgressDialog>
#include <QTimer>
#include <atomic>
#include <memory>

#include "app/gs/DangerController.h"
#include "app/gs/MeshController.h"
#include "app/gs/SamplingController.h"
#include "app/gs/SimulatorSource.h"
#include "app/gs/WalkSession.h"
#include "replay/MissionTimeline.h"
#include "widgets/ConnectDialog.h"
#include "widgets/MainWindow.h"

namespace ambler::gs {

struct StationOptions {
  quint64 seed = 1;                       // the built-in simulator's course
  QString operator_id = "operator";       // who approves
  QString log_dir;                        // where live walks are logged
  sim::ScannerModel scanner;              // for the range-image view's scans
  gait::GaitContext ground;               // what the station plans with
  rover::SimulatedRoverConfig simulator;  // the built-in simulator's rover
  rover::SimulatedGround simulated_ground;  // the built-in simulator's: the course by default
};

// The ground station's wiring (QGroundControl style: the views never know
// what they are connected to): the main window, the built-in simulator's
// scans for the range view, a walk session over whichever link the
// operator chose, or a replayed mission log on a timeline. Every view is
// fed from here.
class GroundStation : public QObject {
  Q_OBJECT

 public:
  explicit GroundStation(StationOptions options, QObject* parent = nullptr);
  ~GroundStation() override;

  widgets::MainWindow& window() { return window_; }
  DangerController& danger() { return danger_; }
  SamplingController& sampling() { return sampling_; }
  MeshController& mesh() { return mesh_; }
  WalkSession* session() const { return session_.get(); }
  const replay::MissionTimeline* timeline() const { return timeline_.get(); }

  // A walk session over `choice` (a rover over DDS now, the built-in
  // simulator at the first walk), or a replay of a log; refused, with why,
  // when the rover cannot be reached.
  Refusal connectTo(const widgets::ConnectChoice& choice);
  // Builds the log's timeline on a worker thread with a progress dialog;
  // replayReady() or an error follows.
  void openLog(const QString& path);
  // Live: the station's walk of `steps` steps along `heading` (straight
  // ahead by default) on the current session.
  void startWalk(int steps, const gait::Heading& heading = {});
  // The Rock sampling tab with a simulated light-striper image of the
  // sampling tray on course `seed` (SamplingController::trayShown follows).
  void showTray(quint64 seed);

 signals:
  void replayReady();
  void proposalShown();  // a step waits for the operator
  void replayFailed(const QString& why);

 private:
  void wireWindow();
  Refusal openSession();  // over choice_
  // The built-in simulator on the ground and seed of the command line.
  widgets::ConnectChoice launchedSimulator() const;
  // The simulator's ground that `choice` picks.
  rover::SimulatedGround groundOf(const widgets::ConnectChoice& choice) const;
  // Shows a refusal to the operator; whether there was one.
  bool report(const Refusal& refusal);
  void showSession();
  void showWalkState();
  QString linkFigures(const WalkState& state, double now_s) const;
  void refreshTelemetry();
  void showReplayAt(double time_s);
  void finishOpening();
  QString newLogPath() const;

  StationOptions options_;
  widgets::MainWindow window_;
  DangerController danger_{*window_.dangerPanel()};
  SamplingController sampling_{*window_.samplingPanel()};
  MeshController mesh_{*window_.meshPanel()};
  SimulatorSource simulator_;
  widgets::ConnectChoice choice_;
  std::unique_ptr<WalkSession> session_;
  std::shared_ptr<const WalkState> shown_;       // the session's state the views show
  std::vector<executive::RoverSample> history_;  // the live walk's
  double session_start_s_ = 0.0;
  std::unique_ptr<replay::MissionTimeline> timeline_;
  std::vector<executive::RoverSample> replay_history_;
  // Opening a log: progress from the worker, cancel from the dialog.
  struct Opening {
    QString path;
    std::atomic<int> done{0}, total{0};
    std::atomic<bool> cancel{false};
    QString error;  // written by the worker before it finishes
  };
  std::shared_ptr<Opening> opening_;
  QFutureWatcher<std::shared_ptr<replay::MissionTimeline>> open_watcher_;
  std::unique_ptr<QProgressDialog> progress_dialog_;
  QTimer progress_timer_;
  QTimer refresh_timer_;
};

}  // namespace ambler::gs
