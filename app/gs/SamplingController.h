#pragma once

#include <QObject>
#include <optional>

#include "sampling/RockSampler.h"

namespace ambler::widgets {
class SamplingPanel;
}

namespace ambler::gs {

// The Rock sampling tab's work (cmu-1990 sampling paper): features and
// automatic seeds of a light-striper image, a contour, superquadric fit
// and grasp from a seed, and what the log keeps of an approved grasp. The
// panel draws what it is given and asks through its signals.
class SamplingController : public QObject {
  Q_OBJECT

 public:
  explicit SamplingController(widgets::SamplingPanel& panel, QObject* parent = nullptr);

  void setImage(sensor::StriperImage image);
  // Contour, fit and grasp from the pixel (row, col); a failure is shown.
  void fitAt(double row, double col, bool robust);
  const std::optional<sampling::RockSample>& sample() const { return sample_; }

 signals:
  // The operator approved `plan`; `fit_json` is what the log keeps of the
  // fit behind it.
  void graspApproved(const ambler::sampling::GraspPlan& plan, const QString& fit_json);

 private:
  widgets::SamplingPanel& panel_;
  std::optional<sensor::StriperImage> image_;
  std::optional<sampling::FeatureMap> features_;
  std::optional<sampling::RockSample> sample_;
  bool robust_ = true;
};

}  // namespace ambler::gs
