#pragma once

#include <QImage>
#include <QWidget>
#include <optional>

#include "executive/ApprovalGate.h"
#include "terrain/ElevationMap.h"

class QComboBox;

namespace ambler::widgets {

// The local terrain map seen from above (issue 7): one layer at a time
// (elevation, sigma, known / unknown / shadow) with its colour bar and
// units, around the rover; on top, the feet of the step waiting for a
// decision, its conservative support polygon and the proposed foothold.
// Hovering reads out the cell; a click asks to move the foothold there.
class MapView : public QWidget {
  Q_OBJECT

 public:
  enum class Shown { kElevation, kSigma, kState };

  explicit MapView(QWidget* parent = nullptr);

  void setMap(const terrain::ElevationMap& map);
  void setProposal(const std::optional<executive::StepProposal>& proposal);
  void setShown(Shown layer);
  Shown shown() const { return shown_; }
  QSize sizeHint() const override { return {520, 520}; }

  // Between the world (x east, y north, metres) and this widget.
  QPointF widgetPointOf(const Eigen::Vector2d& world) const;
  std::optional<Eigen::Vector2d> worldPointAt(const QPointF& widget) const;
  const QString& readout() const { return readout_; }
  QRectF mapRect() const;

 signals:
  void footholdClicked(quint64 proposal, double x_m, double y_m);
  void readoutChanged(const QString& text);

 protected:
  void paintEvent(QPaintEvent*) override;
  void mouseMoveEvent(QMouseEvent* e) override;
  void mousePressEvent(QMouseEvent* e) override;

 private:
  void recolor();
  Box2 viewBox() const;
  void drawColorBar(class QPainter& p) const;
  void drawProposal(class QPainter& p) const;

  std::optional<terrain::ElevationMap> map_;
  std::optional<executive::StepProposal> proposal_;
  Shown shown_ = Shown::kElevation;
  QImage colored_;  // the view box, one pixel per cell
  double lo_ = 0.0, hi_ = 1.0;
  QComboBox* layer_box_;
  QString readout_;
};

}  // namespace ambler::widgets
