#pragma once

#include <QFutureWatcher>
#include <QObject>
#include <optional>

#include "rover/SimulatedGround.h"
#include "sim/ScannerSim.h"
#include "widgets/ScanDisplay.h"

namespace ambler::gs {

// The built-in simulator as a source of scans for the GUI: simulates on a
// worker thread and reports back on the GUI thread: the Scan action's
// single scans, apart from a walk's link.
class SimulatorSource : public QObject {
  Q_OBJECT

 public:
  // On `ground`, drawn from the requested seed.
  explicit SimulatorSource(sim::ScannerModel model, rover::SimulatedGround ground = {},
                           QObject* parent = nullptr);

  void requestScan(quint64 seed);
  // Scans from now on are of `ground`.
  void setGround(rover::SimulatedGround ground) { ground_ = std::move(ground); }

 signals:
  void scanReady(const ambler::widgets::ScanDisplay& display);
  void scanFailed(const QString& message);

 private:
  struct Result {
    std::optional<widgets::ScanDisplay> display;
    QString error;
  };
  static Result simulate(const sim::ScannerModel& model, const rover::SimulatedGround& ground,
                         quint64 seed);

  sim::ScannerModel model_;
  rover::SimulatedGround ground_;
  QFutureWatcher<Result> watcher_;
};

}  // namespace ambler::gs
