#include "app/gs/SimulatorSource.h"

#include <chrono>

#include "app/gs/Background.h"
#include "sim/CourseScene.h"

namespace ambler::gs {

SimulatorSource::SimulatorSource(sim::ScannerModel model, rover::SimulatedGround ground,
                                 QObject* parent)
    : QObject(parent), model_(std::move(model)), ground_(std::move(ground)) {
  connect(&watcher_, &QFutureWatcher<Result>::finished, this, [this] {
    const Result result = watcher_.result();
    if (result.display)
      emit scanReady(*result.display);
    else
      emit scanFailed(result.error);
  });
}

void SimulatorSource::requestScan(quint64 seed) {
  if (watcher_.isRunning()) return;  // one scan at a time, like the sensor
  watcher_.setFuture(runInBackground(
      [model = model_, ground = ground_, seed] { return simulate(model, ground, seed); }));
}

SimulatorSource::Result SimulatorSource::simulate(const sim::ScannerModel& model,
                                                  const rover::SimulatedGround& ground,
                                                  quint64 seed) {
  try {
    const auto start = std::chrono::steady_clock::now();
    const sim::CourseScene scene = ground.scene(seed, model);
    widgets::ScanDisplay display;
    display.scan = scene.scan(seed);
    // The ground around the rover and the scanned area, at 10 cm.
    Box2 area = scene.footprint();
    const Box2 extent = scene.terrain().extent();
    area = {std::max(area.x_min, extent.x_min), std::max(std::min(area.y_min, -4.0), extent.y_min),
            std::min(area.x_max, extent.x_max), std::min(area.y_max, extent.y_max)};
    display.ground_grid = GridSpec::covering(area, 0.1);
    display.ground = sim::sampleHeights(scene.terrain(), display.ground_grid);
    display.scan_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return {std::move(display), {}};
  } catch (const std::exception& e) {
    return {std::nullopt, QString::fromStdString(e.what())};
  }
}

}  // namespace ambler::gs
