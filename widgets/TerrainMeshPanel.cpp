#include "widgets/TerrainMeshPanel.h"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QHBoxLayout>
#include <QHideEvent>
#include <QLabel>
#include <QMouseEvent>
#include <QPainter>
#include <QShowEvent>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <functional>

namespace ambler::widgets {

const QColor kSteeperColour(200, 40, 40);

// The mesh from above, north up, at one scale for both axes.
class MeshTopView : public QWidget {
 public:
  std::shared_ptr<const mapping::TerrainMesh> mesh;
  double max_slope_deg = 20.0;
  std::optional<Eigen::Vector2d> start, goal;
  std::optional<mapping::TerrainPath> path;
  std::function<void(const Eigen::Vector2d&)> clicked;

  QSize sizeHint() const override { return {640, 480}; }

 protected:
  void paintEvent(QPaintEvent*) override {
    QPainter p(this);
    p.fillRect(rect(), QColor(20, 20, 24));
    if (mesh == nullptr || mesh->size() == 0) {
      p.setPen(Qt::white);
      p.drawText(rect(), Qt::AlignCenter,
                 tr("No terrain mesh yet: take a scan (meshing starts when this tab is shown)"));
      return;
    }
    fit();
    p.setRenderHint(QPainter::Antialiasing);
    const double limit = max_slope_deg * M_PI / 180;
    for (int t = 0; t < int(mesh->size()); ++t) {
      QPolygonF tri;
      for (int k = 0; k < 3; ++k) tri << toView(mesh->corner(t, k).head<2>());
      const double slope = mesh->slopeRad(t);
      const QColor fill = slope > limit ? kSteeperColour : slopeColour(slope / limit);
      p.setPen(QPen(QColor(0, 0, 0, 90), 0));
      p.setBrush(fill);
      p.drawPolygon(tri);
    }
    if (path && path->found) {
      p.setPen(QPen(QColor(255, 255, 255, 150), 1, Qt::DotLine));
      p.drawPolyline(line(path->raw));
      p.setPen(QPen(QColor(0, 230, 255), 3));
      p.drawPolyline(line(path->simplified));
    }
    mark(p, start, QColor(60, 220, 60), tr("start"));
    mark(p, goal, QColor(255, 170, 0), tr("goal"));
    legend(p);
  }

  void mousePressEvent(QMouseEvent* e) override {
    if (e->button() != Qt::LeftButton || !clicked || mesh == nullptr || mesh->size() == 0) return;
    clicked(toWorld(e->position()));
  }

 public:
  QPointF toView(const Eigen::Vector2d& xy) const {
    return {origin_.x() + (xy.x() - lo_.x()) * scale_, origin_.y() - (xy.y() - lo_.y()) * scale_};
  }
  Eigen::Vector2d toWorld(const QPointF& v) const {
    return {lo_.x() + (v.x() - origin_.x()) / scale_, lo_.y() + (origin_.y() - v.y()) / scale_};
  }
  void fit() {
    lo_ = mesh->vertices[0].head<2>();
    Eigen::Vector2d hi = lo_;
    for (const auto& v : mesh->vertices)
      lo_ = lo_.cwiseMin(v.head<2>()), hi = hi.cwiseMax(v.head<2>());
    const double margin = 40;
    scale_ = std::min((width() - 2 * margin) / std::max(hi.x() - lo_.x(), 1e-3),
                      (height() - 2 * margin) / std::max(hi.y() - lo_.y(), 1e-3));
    origin_ = QPointF((width() - (hi.x() - lo_.x()) * scale_) / 2,
                      (height() + (hi.y() - lo_.y()) * scale_) / 2);
  }

 private:
  // Green (flat) to yellow (at the limit).
  static QColor slopeColour(double share) {
    const double s = std::clamp(share, 0.0, 1.0);
    return QColor::fromRgbF(float(0.2 + 0.7 * s), float(0.6 + 0.25 * s), float(0.3 - 0.2 * s));
  }
  QPolygonF line(const std::vector<Eigen::Vector3d>& points) const {
    QPolygonF out;
    for (const auto& q : points) out << toView(q.head<2>());
    return out;
  }
  void mark(QPainter& p, const std::optional<Eigen::Vector2d>& at, const QColor& colour,
            const QString& label) const {
    if (!at) return;
    const QPointF c = toView(*at);
    p.setPen(QPen(Qt::black, 1));
    p.setBrush(colour);
    p.drawEllipse(c, 6, 6);
    p.setPen(Qt::white);
    p.drawText(c + QPointF(9, -6), label);
  }
  void legend(QPainter& p) const {
    // Above the bar, the red of triangles steeper than the limit.
    const QRectF steeper(width() - 30, 40, 14, 12);
    const QRectF bar(steeper.left(), steeper.bottom() + 8, 14, height() - 100);
    p.fillRect(steeper, kSteeperColour);
    for (int i = 0; i < int(bar.height()); ++i)
      p.fillRect(QRectF(bar.left(), bar.bottom() - i, bar.width(), 1),
                 slopeColour(i / bar.height()));
    p.setPen(Qt::white);
    p.drawText(QPointF(bar.left() - 70, steeper.top() - 8), tr("Slope [deg]"));
    p.drawText(QRectF(steeper.left() - 64, steeper.top() - 2, 60, 16), Qt::AlignRight,
               tr("> %1").arg(max_slope_deg, 0, 'f', 0));
    p.drawText(QPointF(bar.left() - 26, bar.top() + 10), QString::number(max_slope_deg, 'f', 0));
    p.drawText(QPointF(bar.left() - 14, bar.bottom()), QStringLiteral("0"));
    // Scale bar: 5 m.
    const QPointF a(20, height() - 20), b = a + QPointF(5 * scale_, 0);
    p.drawLine(a, b);
    p.drawText(a + QPointF(0, -5), tr("5 m"));
  }

  Eigen::Vector2d lo_{0, 0};
  double scale_ = 1.0;
  QPointF origin_;
};

TerrainMeshPanel::TerrainMeshPanel(QWidget* parent)
    : QWidget(parent),
      view_(new MeshTopView),
      cost_(new QComboBox),
      max_slope_(new QDoubleSpinBox),
      readout_(new QLabel) {
  cost_->addItem(tr("Shortest distance"), int(mapping::PathCost::kDistance));
  cost_->addItem(tr("Distance and slope"), int(mapping::PathCost::kSlope));
  cost_->addItem(tr("Favour high ground"), int(mapping::PathCost::kHighGround));
  cost_->setCurrentIndex(1);
  max_slope_->setRange(1, 60);
  max_slope_->setValue(20);
  max_slope_->setSuffix(tr(" deg"));
  auto* controls = new QHBoxLayout;
  controls->addWidget(new QLabel(tr("Path cost:")));
  controls->addWidget(cost_);
  controls->addWidget(new QLabel(tr("Slope limit:")));
  controls->addWidget(max_slope_);
  controls->addStretch();
  readout_->setWordWrap(true);
  auto* layout = new QVBoxLayout(this);
  layout->addLayout(controls);
  layout->addWidget(view_, 1);
  layout->addWidget(readout_);
  view_->clicked = [this](const Eigen::Vector2d& xy) { emit picked(xy); };
  connect(cost_, &QComboBox::currentIndexChanged, this, &TerrainMeshPanel::pathOptionsChanged);
  connect(max_slope_, &QDoubleSpinBox::valueChanged, this, [this](double deg) {
    view_->max_slope_deg = deg;
    view_->update();
    emit pathOptionsChanged();
  });
}

void TerrainMeshPanel::showMesh(std::shared_ptr<const mapping::TerrainMesh> mesh) {
  view_->mesh = std::move(mesh);
  view_->update();
}

void TerrainMeshPanel::showPath(std::optional<Eigen::Vector2d> start,
                                std::optional<Eigen::Vector2d> goal,
                                std::optional<mapping::TerrainPath> path) {
  view_->start = start;
  view_->goal = goal;
  view_->path = std::move(path);
  view_->update();
}

void TerrainMeshPanel::setReadout(const QString& text) { readout_->setText(text); }

mapping::PathCost TerrainMeshPanel::pathCost() const {
  return mapping::PathCost(cost_->currentData().toInt());
}

double TerrainMeshPanel::maxSlopeDeg() const { return max_slope_->value(); }

void TerrainMeshPanel::showEvent(QShowEvent* e) {
  QWidget::showEvent(e);
  emit shownChanged(true);
}

void TerrainMeshPanel::hideEvent(QHideEvent* e) {
  QWidget::hideEvent(e);
  emit shownChanged(false);
}

QString TerrainMeshPanel::readout() const { return readout_->text(); }

QWidget* TerrainMeshPanel::meshView() const { return view_; }

QPointF TerrainMeshPanel::viewPointOf(const Eigen::Vector2d& world_xy) const {
  if (!view_->mesh || view_->mesh->size() == 0) return {};
  view_->fit();
  return view_->toView(world_xy);
}

}  // namespace ambler::widgets
