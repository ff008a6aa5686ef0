#include "app/gs/SamplingController.h"

#include <nlohmann/json.hpp>

#include "app/gs/Background.h"
#include "sim/ObstacleCourse.h"
#include "sim/StriperSim.h"
#include "widgets/SamplingPanel.h"

namespace ambler::gs {

namespace {

std::string triple(const Eigen::Vector3d& v) {
  return std::to_string(v.x()) + "," + std::to_string(v.y()) + "," + std::to_string(v.z());
}

// What the mission log keeps of the fit behind a grasp (replay::
// describeDecision reads it back as a sentence).
std::string fitRecord(const sampling::RockSample& s, bool robust) {
  const auto& q = s.fit.shape;
  return nlohmann::json{{"centre_m", triple(q.pose.translation())},
                        {"size_m", triple(q.size)},
                        {"eps1", q.eps1},
                        {"eps2", q.eps2},
                        {"rms_m", s.fit.rms_m},
                        {"points", s.points.size()},
                        {"robust", robust}}
      .dump();
}

}  // namespace

SamplingController::SamplingController(widgets::SamplingPanel& panel, QObject* parent)
    : QObject(parent), panel_(panel) {
  connect(&panel_, &widgets::SamplingPanel::fitRequested, this, &SamplingController::fitAt);
  connect(&panel_, &widgets::SamplingPanel::sceneRequested, this,
          &SamplingController::simulateTray);
  connect(&tray_watcher_, &QFutureWatcher<std::shared_ptr<const Tray>>::finished, this,
          &SamplingController::showTray);
  connect(&fit_watcher_, &QFutureWatcher<Fit>::finished, this, &SamplingController::showFit);
  connect(&panel_, &widgets::SamplingPanel::graspRequested, this, [this] {
    if (sample_ && sample_->grasp.ok)
      emit graspApproved(sample_->grasp, QString::fromStdString(fitRecord(*sample_, robust_)));
  });
}

void SamplingController::simulateTray(quint64 seed) {
  if (tray_watcher_.isRunning()) {
    next_tray_ = seed;  // the newest wish wins
    return;
  }
  tray_watcher_.setFuture(runInBackground([seed]() -> std::shared_ptr<const Tray> {
    const sim::ProceduralTerrain tray(
        sim::makeWorkArea({.seed = seed, .burial_min = 0.0, .burial_max = 0.5}));
    auto made = std::make_shared<Tray>();
    made->seed = seed;
    made->image = sim::simulateStriper(tray, sim::StriperModel{}, seed).image;
    made->features = sampling::extractFeatures(made->image);
    made->seeds = sampling::automaticSeeds(made->image, made->features);
    return made;
  }));
}

void SamplingController::showTray() {
  if (const auto next = std::exchange(next_tray_, std::nullopt)) return simulateTray(*next);
  tray_ = tray_watcher_.result();
  sample_.reset();
  panel_.showImage(tray_->image, tray_->features, tray_->seeds);
  panel_.setSeed(tray_->seed);
  emit trayShown();
}

void SamplingController::fitAt(double row, double col, bool robust) {
  if (!tray_) return;
  if (fit_watcher_.isRunning()) {
    next_fit_ = {{col, row}, robust};  // the newest click wins
    return;
  }
  sampling::SamplingOptions options;
  options.fit.robust = robust;
  fit_watcher_.setFuture(runInBackground([tray = tray_, at = Eigen::Vector2d(col, row), options] {
    Fit fit;
    fit.robust = options.fit.robust;
    fit.tray = tray;
    try {
      fit.sample =
          sampling::sampleRock(tray->image, tray->features, at, options,
                               [&](const sampling::Contour& c) { fit.stages.push_back(c); });
    } catch (const std::invalid_argument& e) {
      fit.failure = QString::fromUtf8(e.what());
    }
    return fit;
  }));
}

void SamplingController::showFit() {
  auto fit = fit_watcher_.result();
  if (const auto next = std::exchange(next_fit_, std::nullopt))
    return fitAt(next->first.y(), next->first.x(), next->second);
  if (fit.tray != tray_) return;  // a new tray came meanwhile
  sample_ = std::move(fit.sample);
  robust_ = fit.robust;
  panel_.showFit(sample_, std::move(fit.stages), fit.robust, fit.failure);
  emit fitted();
}

}  // namespace ambler::gs
