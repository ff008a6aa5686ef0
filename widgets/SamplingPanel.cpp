#include "widgets/SamplingPanel.h"

#include <vtkRenderer.h>

#include <QCheckBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QMouseEvent>
#include <QPainter>
#include <QPushButton>
#include <QSpinBox>
#include <QTimer>
#include <QVBoxLayout>
#include <cmath>

#include "rendering/SceneBuilders.h"
#include "rendering/VtkView.h"

namespace ambler::widgets {

// The intensity image, scaled to fit, with the overlays in pixel
// coordinates (x = column, y = row).
class StriperView : public QWidget {
 public:
  QImage image, features;
  bool show_features = true;
  std::vector<QPointF> seeds;
  QPolygonF contour;
  std::vector<QPolygonF> wireframe;
  std::function<void(double row, double col)> clicked;
  std::function<void(double row, double col)> hovered;

  QRectF imageRect() const {
    if (image.isNull()) return {};
    const double scale =
        std::min(width() / double(image.width()), height() / double(image.height()));
    const QSizeF size(image.width() * scale, image.height() * scale);
    return {QPointF((width() - size.width()) / 2, (height() - size.height()) / 2), size};
  }
  QPointF toView(const QPointF& pixel) const {
    const QRectF r = imageRect();
    return {r.left() + (pixel.x() + 0.5) * r.width() / image.width(),
            r.top() + (pixel.y() + 0.5) * r.height() / image.height()};
  }
  std::optional<QPointF> toPixel(const QPointF& p) const {
    const QRectF r = imageRect();
    if (!r.contains(p)) return std::nullopt;
    return QPointF((p.x() - r.left()) * image.width() / r.width() - 0.5,
                   (p.y() - r.top()) * image.height() / r.height() - 0.5);
  }

 protected:
  void paintEvent(QPaintEvent*) override {
    QPainter p(this);
    p.fillRect(rect(), Qt::black);
    if (image.isNull()) {
      p.setPen(Qt::white);
      p.drawText(rect(), Qt::AlignCenter, tr("No light-striper image yet: take one"));
      return;
    }
    p.drawImage(imageRect(), image);
    if (show_features) p.drawImage(imageRect(), features);
    p.setRenderHint(QPainter::Antialiasing);
    auto mapped = [&](const QPolygonF& poly) {
      QPolygonF out;
      for (const auto& q : poly) out << toView(q);
      return out;
    };
    p.setPen(QPen(QColor(255, 90, 255), 1));
    for (const auto& line : wireframe) p.drawPolyline(mapped(line));
    p.setPen(QPen(QColor(0, 255, 120), 2));
    if (!contour.isEmpty()) p.drawPolygon(mapped(contour));
    p.setPen(QPen(QColor(0, 220, 255), 2));
    for (const auto& s : seeds) {
      const QPointF c = toView(s);
      p.drawLine(c - QPointF(5, 0), c + QPointF(5, 0));
      p.drawLine(c - QPointF(0, 5), c + QPointF(0, 5));
    }
  }
  void mousePressEvent(QMouseEvent* e) override {
    if (e->button() != Qt::LeftButton || !clicked) return;
    if (const auto px = toPixel(e->position())) clicked(px->y(), px->x());
  }
  void mouseMoveEvent(QMouseEvent* e) override {
    if (const auto px = toPixel(e->position()); px && hovered) hovered(px->y(), px->x());
  }
};

namespace {

// Shadows dark blue, range edges red, concave creases yellow.
QImage featureOverlay(const sampling::FeatureMap& f) {
  QImage out(f.cols, f.rows, QImage::Format_ARGB32);
  for (int r = 0; r < f.rows; ++r)
    for (int c = 0; c < f.cols; ++c) {
      const auto k = f.kindAt(r, c);
      QColor color(0, 0, 0, 0);
      if (k & sampling::kShadow) color = QColor(40, 40, 160, 170);
      if (k & sampling::kNormalEdge) color = QColor(255, 230, 0, 200);
      if (k & sampling::kRangeEdge) color = QColor(255, 40, 40, 220);
      out.setPixelColor(c, r, color);
    }
  return out;
}

QImage intensityImage(const sensor::StriperImage& image) {
  QImage out(image.cols(), image.rows(), QImage::Format_Grayscale8);
  for (int r = 0; r < image.rows(); ++r)
    for (int c = 0; c < image.cols(); ++c)
      out.setPixelColor(
          c, r, QColor::fromHsvF(0, 0, std::clamp(image.intensity[image.index(r, c)], 0.0f, 1.0f)));
  return out;
}

// Meridians and parallels of the superquadric, in the world.
std::vector<std::vector<Eigen::Vector3d>> wireframe(const Superquadric& s) {
  std::vector<std::vector<Eigen::Vector3d>> lines;
  for (int m = 0; m < 8; ++m) {
    std::vector<Eigen::Vector3d> line;
    for (int k = 0; k <= 24; ++k)
      line.push_back(s.surfacePoint(-M_PI / 2 + M_PI * k / 24, -M_PI + 2 * M_PI * m / 8));
    lines.push_back(line);
  }
  for (int q = 1; q < 6; ++q) {
    std::vector<Eigen::Vector3d> line;
    for (int k = 0; k <= 32; ++k)
      line.push_back(s.surfacePoint(-M_PI / 2 + M_PI * q / 6, -M_PI + 2 * M_PI * k / 32));
    lines.push_back(line);
  }
  return lines;
}

}  // namespace

SamplingPanel::SamplingPanel(QWidget* parent)
    : QWidget(parent),
      view_(new StriperView),
      points_view_(new rendering::VtkView),
      seed_box_(new QSpinBox),
      robust_(new QCheckBox(tr("Robust fit"))),
      show_features_(new QCheckBox(tr("Show features"))),
      info_(new QLabel),
      approve_(new QPushButton(tr("&Approve grasp"))),
      growth_(new QTimer(this)) {
  view_->setMinimumSize(256, 256);
  view_->setMouseTracking(true);
  view_->setToolTip(tr("Click inside a rock to outline and fit it"));
  robust_->setChecked(true);
  robust_->setToolTip(tr("Fit the superquadric with a robust loss that ignores stray points"));
  show_features_->setChecked(true);
  seed_box_->setRange(1, 999999);
  seed_box_->setToolTip(tr("Seed of the simulated sampling tray"));
  auto* scene = new QPushButton(tr("New tray image"));
  connect(scene, &QPushButton::clicked, this,
          [this] { emit sceneRequested(quint64(seed_box_->value())); });
  approve_->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_G));
  approve_->setToolTip(tr("Send the grasp to the rover, signed and logged (Ctrl+G)"));
  approve_->setEnabled(false);
  info_->setWordWrap(true);
  info_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  info_->setAlignment(Qt::AlignTop | Qt::AlignLeft);
  info_->setText(tr("Click inside a rock, or on a cyan cross (a seed found from a range shadow)."));

  auto* controls = new QHBoxLayout;
  controls->addWidget(new QLabel(tr("Tray seed:")));
  controls->addWidget(seed_box_);
  controls->addWidget(scene);
  controls->addWidget(show_features_);
  controls->addWidget(robust_);
  controls->addStretch(1);
  auto* right = new QVBoxLayout;
  right->addWidget(points_view_, 1);
  right->addWidget(info_);
  right->addWidget(approve_);
  auto* body = new QHBoxLayout;
  body->addWidget(view_, 3);
  body->addLayout(right, 2);
  auto* layout = new QVBoxLayout(this);
  layout->addLayout(controls);
  layout->addLayout(body, 1);

  view_->clicked = [this](double row, double col) {
    if (image_) emit fitRequested(row, col, robust_->isChecked());
  };
  view_->hovered = [this](double row, double col) {
    if (!image_) return;
    const int r = int(std::lround(row)), c = int(std::lround(col));
    if (r < 0 || c < 0 || r >= image_->rows() || c >= image_->cols()) return;
    QString text = tr("row %1, col %2").arg(r).arg(c);
    if (image_->hasPoint(r, c)) {
      const auto p = image_->point(r, c);
      text += tr(": x %1, y %2, z %3 m")
                  .arg(p.x(), 0, 'f', 3)
                  .arg(p.y(), 0, 'f', 3)
                  .arg(p.z(), 0, 'f', 3);
    } else {
      text += tr(": no measurement (range shadow)");
    }
    view_->setToolTip(text);
  };
  connect(show_features_, &QCheckBox::toggled, this, [this](bool on) {
    view_->show_features = on;
    view_->update();
  });
  connect(robust_, &QCheckBox::toggled, this, [this](bool robust) {
    if (sample_) emit fitRequested(sample_->seed.y(), sample_->seed.x(), robust);
  });
  connect(approve_, &QPushButton::clicked, this, [this] {
    if (!sample_ || !sample_->grasp.ok) return;
    approve_->setEnabled(false);  // once per fit
    emit graspRequested();
  });
  connect(growth_, &QTimer::timeout, this, [this] {
    if (shown_stage_ + 1 < stages_.size()) {
      ++shown_stage_;
    } else {
      growth_->stop();
      // The fit is shown whole before it can be approved.
      approve_->setEnabled(sample_ && sample_->grasp.ok);
    }
    showSample();
  });
}

SamplingPanel::~SamplingPanel() = default;

QWidget* SamplingPanel::imageView() const { return view_; }

QPointF SamplingPanel::viewPointOf(double row, double col) const {
  return view_->toView(QPointF(col, row));
}

void SamplingPanel::showImage(sensor::StriperImage image, sampling::FeatureMap features,
                              std::vector<sampling::Seed> seeds) {
  image_ = std::move(image);
  features_ = std::move(features);
  seeds_ = std::move(seeds);
  sample_.reset();
  stages_.clear();
  view_->image = intensityImage(*image_);
  view_->features = featureOverlay(*features_);
  view_->seeds.clear();
  for (const auto& s : seeds_) view_->seeds.emplace_back(s.pixel.x(), s.pixel.y());
  approve_->setEnabled(false);
  info_->setText(
      tr("%1 possible rock(s) found from range shadows (cyan). Click inside a rock to fit it.")
          .arg(seeds_.size()));
  showSample();
}

void SamplingPanel::showFit(std::optional<sampling::RockSample> sample,
                            std::vector<sampling::Contour> stages, bool robust,
                            const QString& failure) {
  sample_ = std::move(sample);
  stages_ = std::move(stages);
  robust_fit_ = robust;
  if (!sample_) {
    growth_->stop();
    approve_->setEnabled(false);
    info_->setText(tr("No fit: %1").arg(failure));
    showSample();
    return;
  }
  shown_stage_ = 0;
  growth_->start(25);  // the contour grows on screen, then the fit appears
  showSample();
  showPoints();
  info_->setText(describeSample());
  approve_->setEnabled(false);  // until the contour has grown on screen
}

void SamplingPanel::setSeed(quint64 seed) { seed_box_->setValue(int(seed)); }

void SamplingPanel::setGraspAnswer(const QString& text, bool ok) {
  info_->setText(describeSample() + "<br><b style='color:" + (ok ? "#1b5e20" : "#b71c1c") + "'>" +
                 text.toHtmlEscaped() + "</b>");
}

void SamplingPanel::showSample() {
  view_->contour.clear();
  view_->wireframe.clear();
  if (sample_) {
    const bool growing = growth_->isActive() && shown_stage_ < stages_.size();
    const auto& contour = growing ? stages_[shown_stage_] : sample_->contour;
    for (const auto& p : contour.points) view_->contour << QPointF(p.x(), p.y());
    if (!growing)
      for (const auto& line : wireframe(sample_->fit.shape)) {
        QPolygonF poly;
        for (const auto& w : line) {
          const Eigen::Vector2d pixel = image_->camera.pixelOf(w);
          poly << QPointF(pixel.x(), pixel.y());
        }
        view_->wireframe.push_back(poly);
      }
  }
  view_->update();
}

void SamplingPanel::showPoints() {
  points_view_->clear();
  if (!sample_) return points_view_->render();
  std::vector<Eigen::Vector3f> points;
  for (const auto& p : sample_->points) points.push_back(p.cast<float>());
  points_view_->add(rendering::makePointCloud(points, {0.9, 0.9, 0.9}, 3.0f));
  points_view_->add(
      rendering::makePolylines(wireframe(sample_->fit.shape), {1.0, 0.35, 1.0}, 1.5f));
  points_view_->edit([](vtkRenderer& renderer) { renderer.ResetCamera(); });
  points_view_->render();
}

QString SamplingPanel::describeSample() const {
  if (!sample_) return {};
  const auto& s = *sample_;
  const auto& q = s.fit.shape;
  const Eigen::Vector3d c = q.pose.translation();
  QString text =
      tr("<b>Superquadric</b> (%1 LM on the radial distance%14, %2 points, %3 ms)<br>"
         "centre x %4, y %5, z %6 m<br>size %7 x %8 x %9 cm, roundness eps1 %10, eps2 %11<br>"
         "fit residual %12 mm rms, %13 % of the points kept")
          .arg(robust_fit_ ? tr("robust") : tr("plain"))
          .arg(s.points.size())
          .arg(s.fit_ms, 0, 'f', 1)
          .arg(c.x(), 0, 'f', 3)
          .arg(c.y(), 0, 'f', 3)
          .arg(c.z(), 0, 'f', 3)
          .arg(2 * q.size.x() * 100, 0, 'f', 1)
          .arg(2 * q.size.y() * 100, 0, 'f', 1)
          .arg(2 * q.size.z() * 100, 0, 'f', 1)
          .arg(q.eps1, 0, 'f', 2)
          .arg(q.eps2, 0, 'f', 2)
          .arg(s.fit.rms_m * 1000, 0, 'f', 2)
          .arg(s.fit.inlier_share * 100, 0, 'f', 0)
          .arg(s.sand ? tr(", resting on the sand plane") : QString());
  if (s.grasp.ok)
    text += tr("<br><b>Grasp</b> at x %1, y %2, jaws down to z %3 m, main axis %4°, opening %5 cm")
                .arg(s.grasp.centre.x(), 0, 'f', 3)
                .arg(s.grasp.centre.y(), 0, 'f', 3)
                .arg(s.grasp.centre.z(), 0, 'f', 3)
                .arg(s.grasp.yaw_rad * 180 / M_PI, 0, 'f', 1)
                .arg(s.grasp.opening_m * 100, 0, 'f', 1);
  else
    text += tr("<br><b style='color:#b71c1c'>No grasp: %1</b>")
                .arg(QString::fromStdString(s.grasp.reason).toHtmlEscaped());
  return text;
}

}  // namespace ambler::widgets
