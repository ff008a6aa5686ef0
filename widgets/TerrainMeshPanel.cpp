#include "widgets/TerrainMeshPanel.h"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QMouseEvent>
#include <QPainter>
#include <QShowEvent>
#include <QVBoxLayout>
#include <QtConcurrent/QtConcurrentRun>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>

namespace ambler::widgets {

// The mesh from above, north up, at one scale for both axes.
class MeshTopView : public QWidget {
 public:
  const mapping::TerrainMesh* mesh = nullptr;
  double max_slope_deg = 20.0;
  std::optional<Eigen::Vector2d> start, goal;
  const mapping::TerrainPath* path = nullptr;
  std::function<void(const Eigen::Vector2d&)> clicked;

  QSize sizeHint() const override { return {640, 480}; }

 protected:
  void paintEvent(QPaintEvent*) override {
    QPainter p(this);
    p.fillRect(rect(), QColor(20, 20, 24));
    if (mesh == nullptr || mesh->size() == 0) {
      p.setPen(Qt::white);
      p.drawText(rect(), Qt::AlignCenter, tr("No terrain mesh yet: take a scan"));
      return;
    }
    fit();
    p.setRenderHint(QPainter::Antialiasing);
    const double limit = max_slope_deg * M_PI / 180;
    for (int t = 0; t < int(mesh->size()); ++t) {
      QPolygonF tri;
      for (int k = 0; k < 3; ++k) tri << toView(mesh->corner(t, k).head<2>());
      const double slope = mesh->slopeRad(t);
      const QColor fill = slope > limit ? QColor(200, 40, 40) : slopeColour(slope / limit);
      p.setPen(QPen(QColor(0, 0, 0, 90), 0));
      p.setBrush(fill);
      p.drawPolygon(tri);
    }
    if (path != nullptr && path->found) {
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
    const QRectF bar(width() - 30, 40, 14, height() - 80);
    for (int i = 0; i < int(bar.height()); ++i)
      p.fillRect(QRectF(bar.left(), bar.bottom() - i, bar.width(), 1),
                 slopeColour(i / bar.height()));
    p.setPen(Qt::white);
    p.drawText(QPointF(bar.left() - 70, bar.top() - 8), tr("Slope [deg]"));
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
  view_->mesh = &mesh_;
  view_->clicked = [this](const Eigen::Vector2d& xy) { pick(xy); };
  connect(cost_, &QComboBox::currentIndexChanged, this, [this] { plan(); });
  connect(max_slope_, &QDoubleSpinBox::valueChanged, this, [this] { plan(); });
  // The chain is bookkeeping for this tab: it waits while the operator's
  // views and the walk need the cores.
  background_.setMaxThreadCount(1);
  background_.setThreadPriority(QThread::IdlePriority);
  connect(&watcher_, &QFutureWatcher<mapping::Registration>::finished, this,
          &TerrainMeshPanel::takeRegistration);
  refresh();
}

void TerrainMeshPanel::setScan(const sensor::RangeImage& scan) {
  dropWalkScans();
  useCloud(scan.pointsInWorld());
}

void TerrainMeshPanel::clearWalkScans() {
  const bool shown = !chain_.registered().empty();
  dropWalkScans();
  refresh();
  if (shown) emit overlayChanged();  // the 3-D view drops them too
}

// A registration under way finishes into nothing: the chain drops it.
void TerrainMeshPanel::dropWalkScans() { chain_.clear(); }

void TerrainMeshPanel::addWalkScan(const sensor::RangeImage& scan) {
  chain_.add(scan.pointsInWorld());
  registerNext();
  refresh();
}

// ICP takes about a second: off the GUI thread, one scan at a time. A scan
// that joins the chain (the reference at once, the others registered) is
// merged into the mesh's cloud.
void TerrainMeshPanel::registerNext() {
  if (watcher_.isRunning()) return;
  const std::size_t before = chain_.registered().size();
  const auto job = chain_.next();
  if (chain_.registered().size() != before) useCloud(chain_.merged());
  if (!job) return;
  icp_start_ = std::chrono::steady_clock::now();
  watcher_.setFuture(
      QtConcurrent::run(&background_, [job = *job] { return mapping::ScanChain::run(job); }));
}

void TerrainMeshPanel::takeRegistration() {
  icp_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - icp_start_)
                .count();
  const std::size_t before = chain_.registered().size();
  chain_.finish(watcher_.result());  // dropped if the chain was cleared meanwhile
  if (chain_.registered().size() != before) useCloud(chain_.merged());
  registerNext();
}

void TerrainMeshPanel::useCloud(mapping::Cloud cloud) {
  cloud_ = std::move(cloud);
  const bool had_overlay = mesh_.size() > 0;
  mesh_ = {};
  start_.reset(), goal_.reset(), path_.reset();
  // Meshing a full scan takes a fifth of a second: only when looked at.
  if (isVisible())
    buildMesh();
  else if (had_overlay || !chain_.registered().empty())
    emit overlayChanged();  // the old mesh is gone; the scans changed
  refresh();
}

void TerrainMeshPanel::showEvent(QShowEvent* e) {
  QWidget::showEvent(e);
  if (mesh_.size() == 0 && cloud_.size() >= 3) {
    buildMesh();
    refresh();
  }
}

void TerrainMeshPanel::buildMesh() {
  const auto start = std::chrono::steady_clock::now();
  mesh_ = cloud_.size() >= 3 ? mapping::triangulate(cloud_) : mapping::TerrainMesh{};
  mesh_ms_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  emit overlayChanged();
}

void TerrainMeshPanel::pick(const Eigen::Vector2d& xy) {
  if (!start_ || goal_) {
    start_ = xy;
    goal_.reset();
    const bool had_path = path_.has_value();
    path_.reset();
    refresh();
    if (had_path) emit overlayChanged();
    return;
  }
  goal_ = xy;
  plan();
}

void TerrainMeshPanel::plan() {
  if (!start_ || !goal_ || mesh_.size() == 0) return refresh();
  mapping::PathOptions options;
  options.cost = mapping::PathCost(cost_->currentData().toInt());
  options.max_slope_deg = max_slope_->value();
  const auto start = std::chrono::steady_clock::now();
  path_ = mapping::planPath(mesh_, *start_, *goal_, options);
  path_ms_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  refresh();
  emit overlayChanged();
}

QString TerrainMeshPanel::readout() const { return readout_->text(); }

QWidget* TerrainMeshPanel::meshView() const { return view_; }

std::vector<std::vector<Eigen::Vector3d>> TerrainMeshPanel::outlines() const {
  std::vector<std::vector<Eigen::Vector3d>> out;
  for (int t = 0; t < int(mesh_.size()); ++t)
    out.push_back({mesh_.corner(t, 0), mesh_.corner(t, 1), mesh_.corner(t, 2), mesh_.corner(t, 0)});
  return out;
}

std::vector<Eigen::Vector3d> TerrainMeshPanel::pathPoints() const {
  return path_ && path_->found ? path_->simplified : std::vector<Eigen::Vector3d>{};
}

QPointF TerrainMeshPanel::viewPointOf(const Eigen::Vector2d& world_xy) const {
  view_->fit();
  return view_->toView(world_xy);
}

const mapping::TerrainMesh& TerrainMeshPanel::mesh() {
  if (mesh_.size() == 0 && cloud_.size() >= 3) buildMesh(), refresh();
  return mesh_;
}

void TerrainMeshPanel::refresh() {
  view_->start = start_;
  view_->goal = goal_;
  view_->path = path_ ? &*path_ : nullptr;
  view_->max_slope_deg = max_slope_->value();
  QString text;
  const auto& registered = chain_.registered();
  if (registered.size() > 1) {
    const Eigen::Isometry3d& correction = chain_.last().transform;
    const Eigen::Vector3d t = correction.translation();
    text = tr("%1 walk scans registered and merged; the last moved %2 m and %3° by ICP "
              "(rms %4 cm, %5 s). ")
               .arg(registered.size())
               .arg(t.norm(), 0, 'f', 3)
               .arg(Eigen::AngleAxisd(correction.linear()).angle() * 180 / M_PI, 0, 'f', 2)
               .arg(100 * chain_.last().rms_m, 0, 'f', 1)
               .arg(icp_ms_ / 1000, 0, 'f', 1);
  }
  if (chain_.waiting() > 0 || chain_.busy())
    text += tr("Registering %1 scan(s)… ").arg(chain_.waiting() + (chain_.busy() ? 1 : 0));
  if (mesh_.size() > 0)
    text += tr("Mesh%1: %2 triangles, %3 vertices (%4 ms). ")
                .arg(registered.size() > 1 ? tr(" of the merged scans") : tr(" of the last scan"))
                .arg(mesh_.size())
                .arg(mesh_.vertices.size())
                .arg(mesh_ms_, 0, 'f', 0);
  if (!start_)
    text += tr("Click the start.");
  else if (!goal_)
    text += tr("Start at x %1, y %2 m; click the goal.")
                .arg(start_->x(), 0, 'f', 1)
                .arg(start_->y(), 0, 'f', 1);
  else if (path_ && path_->found)
    text += tr("Path: %1 m, %2 waypoints (%3 before simplifying), cost %4 (raw %5), %6 ms.")
                .arg(path_->length_m, 0, 'f', 2)
                .arg(path_->simplified.size())
                .arg(path_->raw.size())
                .arg(path_->simplified_cost, 0, 'f', 1)
                .arg(path_->raw_cost, 0, 'f', 1)
                .arg(path_ms_, 0, 'f', 1);
  else if (path_)
    text += tr("No path: %1.").arg(QString::fromStdString(path_->reason));
  readout_->setText(text);
  view_->update();
}

}  // namespace ambler::widgets
