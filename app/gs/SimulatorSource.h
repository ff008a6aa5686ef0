#pragma once

#include <QFutureWatcher>
#include <QObject>
#include <optional>

#include "sim/ScannerSim.h"
#include "widgets/ScanDisplay.h"

#include "sim/HeightfieldTerrain.h"

namespace ambler::gs {

// The built-in simulator as a source of scans for the GUI: simulates on a
// worker thread and reports back on the GUI thread: the Scan action's
// single scans, apart from a walk's link.
class SimulatorSource : public QObject {
  Q_OBJECT

 public:
  // On `dtm` when given, else on the course of the requested seed.
  explicit SimulatorSource(sim::ScannerModel model, std::optional<sim::DtmSource> dtm = {},
                           QObject* parent = nullptr);

  void requestScan(quint64 seed);

 signals:
  void scanReady(const ambler::widgets::ScanDisplay& display);
  void scanFailed(const QString& message);

 private:
  struct Result {
    std::optional<widgets::ScanDisplay> display;
    QString error;
  };
  static Result simulate(const sim::ScannerModel& model, const std::optional<sim::DtmSource>& dtm,
                         quint64 seed);

  sim::ScannerModel model_;
  std::optional<sim::DtmSource> dtm_;
  QFutureWatcher<Result> watcher_;
};

}  // namespace ambler::gs
