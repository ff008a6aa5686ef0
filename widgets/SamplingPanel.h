#pragma once

#include <QWidget>
#include <optional>
#include <vector>

#include "sampling/RockSampler.h"

class QCheckBox;
class QLabel;
class QPushButton;
class QSpinBox;
class QTimer;

namespace ambler::rendering {
class VtkView;
}

namespace ambler::widgets {

class StriperView;

// Rock sampling (issue 8, cmu-1990 sampling paper): the light-striper's
// intensity image with its features (shadows blue, range edges red,
// creases yellow) and the automatic seeds (cyan); a click inside a rock
// grows a contour (green, shown as it grows), fits a superquadric (magenta
// wireframe over the image and over the rock's points in 3-D), plans the
// clam-shell grasp and, once shown, offers it for approval.
class SamplingPanel : public QWidget {
  Q_OBJECT

 public:
  explicit SamplingPanel(QWidget* parent = nullptr);
  ~SamplingPanel() override;

  // A new image: features and automatic seeds are computed at once.
  void setImage(sensor::StriperImage image);
  // Contour, fit and grasp from the pixel (row, col); an error is shown.
  void fitAt(double row, double col);
  void setSeed(quint64 seed);  // of the simulated tray shown
  // What came of an approved grasp (sent, or why not).
  void setGraspAnswer(const QString& text, bool ok);

  const std::optional<sampling::RockSample>& sample() const { return sample_; }
  const std::vector<sampling::Seed>& seeds() const { return seeds_; }
  // Where image pixel (row, col) is on the image view, for clicks.
  QPointF viewPointOf(double row, double col) const;
  QWidget* imageView() const;
  QPushButton* approveButton() const { return approve_; }
  QLabel* info() const { return info_; }
  QCheckBox* robustBox() const { return robust_; }
  rendering::VtkView* pointView() const { return points_view_; }

 signals:
  void sceneRequested(quint64 seed);
  void graspApproved(const sampling::GraspPlan& plan, const QString& fit_json);

 private:
  void showSample();
  void showPoints();
  QString describeSample() const;

  StriperView* view_;
  rendering::VtkView* points_view_;
  QSpinBox* seed_box_;
  QCheckBox* robust_;
  QCheckBox* show_features_;
  QLabel* info_;
  QPushButton* approve_;
  QTimer* growth_;
  std::optional<sensor::StriperImage> image_;
  std::optional<sampling::FeatureMap> features_;
  std::vector<sampling::Seed> seeds_;
  std::optional<sampling::RockSample> sample_;
  std::vector<sampling::Contour> stages_;  // the contour as it grew
  std::size_t shown_stage_ = 0;
};

}  // namespace ambler::widgets
