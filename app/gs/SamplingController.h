#pragma once

#include <QFutureWatcher>
#include <QObject>
#include <memory>
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

  // A simulated light-striper image of the sampling tray on course `seed`
  // (rocks from resting on the sand to half buried), made with its
  // features and seeds on a worker thread; trayShown() follows.
  void simulateTray(quint64 seed);
  // Contour, fit and grasp from the pixel (row, col), on a worker thread;
  // the panel shows the result or why there is none, then fitted().
  void fitAt(double row, double col, bool robust);
  const std::optional<sampling::RockSample>& sample() const { return sample_; }

 signals:
  // The operator approved `plan`; `fit_json` is what the log keeps of the
  // fit behind it.
  void graspApproved(const ambler::sampling::GraspPlan& plan, const QString& fit_json);
  void trayShown();
  void fitted();

 private:
  struct Tray {
    quint64 seed = 0;
    sensor::StriperImage image;
    sampling::FeatureMap features;
    std::vector<sampling::Seed> seeds;
  };
  void showTray();
  struct Fit {
    std::optional<sampling::RockSample> sample;
    std::vector<sampling::Contour> stages;
    QString failure;
    bool robust = true;
    std::shared_ptr<const Tray> tray;  // the one it fitted
  };
  void showFit();

  widgets::SamplingPanel& panel_;
  QFutureWatcher<std::shared_ptr<const Tray>> tray_watcher_;
  std::shared_ptr<const Tray> tray_;  // the one shown
  std::optional<quint64> next_tray_;  // asked for while one was being made
  QFutureWatcher<Fit> fit_watcher_;
  std::optional<std::pair<Eigen::Vector2d, bool>> next_fit_;  // a click while fitting
  std::optional<sampling::RockSample> sample_;
  bool robust_ = true;
};

}  // namespace ambler::gs
