#pragma once

#include <QImage>
#include <QWidget>
#include <optional>

#include "executive/ApprovalGate.h"
#include "terrain/ElevationMap.h"
#include "widgets/RoverDisplay.h"

class QComboBox;

namespace ambler::widgets {

// The local terrain map seen from above: one layer at a time
// (elevation, sigma, known / oblique / unknown / shadow, and the proposed leg's
// footfall criterion and composite cost over its search region) with its
// colour bar and units, around the rover; on top, the rover's feet and
// conservative support polygon (of the step waiting for a decision, else as
// reported), the proposed foothold, the leg's path to it and the body's.
// Hovering reads out the cell; a click asks to move the foothold there.
class MapView : public QWidget {
  Q_OBJECT

 public:
  enum class Shown { kElevation, kSigma, kState, kCriterion, kComposite };

  explicit MapView(QWidget* parent = nullptr);

  void setMap(const terrain::ElevationMap& map);
  void clear();  // back to "No terrain map yet"
  void setProposal(const std::optional<executive::StepProposal>& proposal);
  // The rover as it reports itself, drawn (and followed) when no step is
  // proposed: a walk between steps, or a replay.
  // The rover drawn: the stance a pending step starts from, else the
  // reported one.
  void setRover(const std::optional<RoverDisplay>& rover);
  void setShown(Shown layer);
  Shown shown() const { return shown_; }
  // Whether a click moves the proposed foothold (not in a replay).
  void setFootholdEditable(bool on);
  const std::optional<terrain::ElevationMap>& map() const { return map_; }
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
  // A click would move the proposed foothold: a leg step shown, editing on.
  bool footholdEditable() const;
  Box2 viewBox() const;
  void drawColorBar(class QPainter& p) const;
  void drawProposal(class QPainter& p) const;
  void drawRover(class QPainter& p, const RoverDisplay& rover) const;
  void drawPaths(class QPainter& p) const;
  // The proposal's cost map shown, if a cost layer is chosen and there is one.
  const footfall::ScoreMap* costShown() const;
  QColor baseColor(int row, int col, const terrain::Layer& values) const;

  std::optional<terrain::ElevationMap> map_;
  std::optional<executive::StepProposal> proposal_;
  bool foothold_editable_ = true;
  std::optional<RoverDisplay> rover_;
  Shown shown_ = Shown::kElevation;
  QImage colored_;                        // the view box, one pixel per cell
  double lo_ = 0.0, hi_ = 1.0;            // the colour bar's range
  double base_lo_ = 0.0, base_hi_ = 1.0;  // the map layer's, under any cost
  bool scale_known_ = false;              // some value in view sets lo_, hi_
  QComboBox* layer_box_;
  QString readout_;
};

}  // namespace ambler::widgets
