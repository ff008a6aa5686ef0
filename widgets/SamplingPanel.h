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

// Rock sampling (cmu-1990 sampling paper): draws the
// light-striper's intensity image with its features (shadows blue, range
// edges red, creases yellow) and the automatic seeds (cyan); a click inside
// a rock asks for a fit, whose contour is shown growing (green), then the
// superquadric (magenta wireframe over the image and over the rock's points
// in 3-D) and the clam-shell grasp, offered for approval. The work is
// SamplingController's (app/gs).
class SamplingPanel : public QWidget {
  Q_OBJECT

 public:
  explicit SamplingPanel(QWidget* parent = nullptr);
  ~SamplingPanel() override;

  // A new image with its features and automatic seeds.
  void showImage(sensor::StriperImage image, sampling::FeatureMap features,
                 std::vector<sampling::Seed> seeds);
  // A fit (its contour grows on screen through `stages`, then the fit and
  // its grasp appear and can be approved), or none and why.
  void showFit(std::optional<sampling::RockSample> sample, std::vector<sampling::Contour> stages,
               bool robust, const QString& failure = {});
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
  // A click inside the image, or the robust switch with a fit shown.
  void fitRequested(double row, double col, bool robust);
  // The operator approved the grasp shown.
  void graspRequested();

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
  bool robust_fit_ = true;  // how the shown fit was made
};

}  // namespace ambler::widgets
