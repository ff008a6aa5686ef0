#include "app/gs/SamplingController.h"

#include <nlohmann/json.hpp>

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
  connect(&panel_, &widgets::SamplingPanel::graspRequested, this, [this] {
    if (sample_ && sample_->grasp.ok)
      emit graspApproved(sample_->grasp, QString::fromStdString(fitRecord(*sample_, robust_)));
  });
}

void SamplingController::setImage(sensor::StriperImage image) {
  image_ = std::move(image);
  features_ = sampling::extractFeatures(*image_);
  sample_.reset();
  panel_.showImage(*image_, *features_, sampling::automaticSeeds(*image_, *features_));
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
