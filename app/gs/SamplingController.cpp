#include "app/gs/SamplingController.h"

#include <QtConcurrent/QtConcurrentRun>
#include <nlohmann/json.hpp>

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
  connect(&tray_watcher_, &QFutureWatcher<std::shared_ptr<Tray>>::finished, this,
          &SamplingController::showTray);
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
  tray_watcher_.setFuture(QtConcurrent::run([seed] {
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
  const auto tray = tray_watcher_.result();
  image_ = tray->image;
  features_ = tray->features;
  sample_.reset();
  panel_.showImage(tray->image, tray->features, tray->seeds);
  panel_.setSeed(tray->seed);
  emit trayShown();
}

void SamplingController::fitAt(double row, double col, bool robust) {
  if (!image_) return;
  sampling::SamplingOptions options;
  options.fit.robust = robust_ = robust;
  std::vector<sampling::Contour> stages;
  try {
    sample_ = sampling::sampleRock(*image_, *features_, {col, row}, options,
                                   [&](const sampling::Contour& c) { stages.push_back(c); });
  } catch (const std::invalid_argument& e) {
    sample_.reset();
    panel_.showFit(std::nullopt, {}, robust, QString::fromUtf8(e.what()));
    return;
  }
  panel_.showFit(sample_, std::move(stages), robust);
}

}  // namespace ambler::gs
