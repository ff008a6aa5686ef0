#include "widgets/DangerPanel.h"

#include <QFileDialog>
#include <QHBoxLayout>
#include <QLabel>
#include <QPainter>
#include <QPushButton>
#include <QVBoxLayout>
#include <chrono>
#include <cmath>

#include "core/Resources.h"
#include "rendering/ColorMap.h"
#include "vision/DangerMap.h"

namespace ambler::widgets {

// The image with D blended over it, the bands, the route; a colour bar.
class DangerImageView : public QWidget {
 public:
  QImage picture;  // grey image with D over the ground
  vision::Bands bands;
  const vision::RoughRoute* route = nullptr;

  QSize sizeHint() const override { return {720, 480}; }

 protected:
  void paintEvent(QPaintEvent*) override {
    QPainter p(this);
    p.fillRect(rect(), QColor(20, 20, 24));
    if (picture.isNull()) {
      p.setPen(Qt::white);
      p.drawText(rect(), Qt::AlignCenter, tr("No camera image yet: open one"));
      return;
    }
    const QRectF area = imageRect();
    p.drawImage(area, picture);
    p.setRenderHint(QPainter::Antialiasing);
    const double scale = area.width() / picture.width();
    auto toView = [&](const vision::ImagePoint& q) {
      return QPointF(area.left() + (q.x + 0.5) * scale,
                     area.top() + (picture.height() - 1 - q.y + 0.5) * scale);
    };
    // The distance bands (§4.2).
    p.setPen(QPen(QColor(255, 255, 255, 170), 1, Qt::DashLine));
    const std::array<std::pair<int, QString>, 3> lines{{{bands.y_v, tr("short | middle")},
                                                        {bands.y_g, tr("middle | long")},
                                                        {bands.y_h, tr("horizon")}}};
    for (const auto& [y, label] : lines) {
      if (y >= picture.height()) continue;
      const double v = toView({0, double(y)}).y();
      p.drawLine(QPointF(area.left(), v), QPointF(area.right(), v));
      p.drawText(QPointF(area.left() + 4, v - 3), label);
    }
    if (route && route->found) {
      QPolygonF line;
      for (const auto& q : route->route) line << toView(q);
      p.setPen(QPen(QColor(0, 230, 255), 3));
      p.drawPolyline(line);
      auto mark = [&](const vision::ImagePoint& q, const QColor& colour, const QString& text) {
        p.setPen(QPen(Qt::black, 1));
        p.setBrush(colour);
        p.drawEllipse(toView(q), 6, 6);
        p.setPen(Qt::white);
        p.drawText(toView(q) + QPointF(8, -6), text);
      };
      mark(route->start, QColor(60, 220, 60), tr("SA"));
      for (std::size_t i = 0; i < route->way_areas.size(); ++i)
        mark(route->way_areas[i], QColor(255, 170, 0), tr("WA%1").arg(i + 1));
      mark(route->destination, QColor(255, 80, 80), tr("DA"));
    }
    colourBar(p, area);
  }

 private:
  QRectF imageRect() const {
    const QRectF space(8, 8, width() - 100, height() - 16);
    const double s = std::min(space.width() / picture.width(), space.height() / picture.height());
    return {space.topLeft(), QSizeF(picture.width() * s, picture.height() * s)};
  }
  void colourBar(QPainter& p, const QRectF& area) {
    const QRectF bar(area.right() + 24, area.top() + 24, 16, std::max(60.0, area.height() - 48));
    for (int y = 0; y < int(bar.height()); ++y) {
      const auto c = rendering::viridis(1.0 - y / bar.height());
      p.setPen(QColor(c[0], c[1], c[2]));
      p.drawLine(QPointF(bar.left(), bar.top() + y), QPointF(bar.right(), bar.top() + y));
    }
    p.setPen(Qt::white);
    p.setBrush(Qt::NoBrush);
    p.drawRect(bar);
    p.drawText(QPointF(bar.left() - 14, bar.top() - 8), tr("D [0-1]"));
    for (int i = 0; i <= 4; ++i) {
      const double y = bar.top() + i * bar.height() / 4;
      p.drawText(QPointF(bar.right() + 4, y + 4), QString::number(1.0 - i * 0.25, 'f', 2));
    }
  }
};

namespace {

// Grey where D is NaN (sky), else the grey blended with viridis(D).
QImage blended(const io::FloatImage& grey, const io::FloatImage& danger) {
  QImage out(grey.cols, grey.rows, QImage::Format_RGB32);
  for (int r = 0; r < grey.rows; ++r)
    for (int c = 0; c < grey.cols; ++c) {
      const int g = std::clamp(int(grey(r, c)), 0, 255);
      const float d = danger(r, c);
      if (!std::isfinite(d)) {
        out.setPixel(c, r, qRgb(g, g, g));
        continue;
      }
      const auto v = rendering::viridis(d);
      out.setPixel(c, r, qRgb((g + 2 * v[0]) / 3, (g + 2 * v[1]) / 3, (g + 2 * v[2]) / 3));
    }
  return out;
}

}  // namespace

DangerPanel::DangerPanel(QWidget* parent)
    : QWidget(parent), view_(new DangerImageView), readout_(new QLabel) {
  QString camera_error;
  try {
    camera_ = vision::readCameraFile(findResource("config/camera.json"));
  } catch (const std::exception& e) {  // the built-in defaults, and say so
    camera_error = tr("Camera file unusable (%1); using the built-in camera. ").arg(e.what());
  }
  auto* open = new QPushButton(tr("Open camera image…"));
  auto* bar = new QHBoxLayout;
  bar->addWidget(open);
  auto* camera = new QLabel(tr("Camera: %1 rows, axis %2° from the vertical, %3° field of view, "
                               "%4 m up (config/camera.json)")
                                .arg(camera_.camera.rows)
                                .arg(camera_.camera.alpha_deg)
                                .arg(camera_.camera.beta_deg)
                                .arg(camera_.camera.height_m));
  camera->setWordWrap(true);
  bar->addWidget(camera, 1);
  readout_->setWordWrap(true);
  auto* layout = new QVBoxLayout(this);
  layout->addLayout(bar);
  layout->addWidget(view_, 1);
  layout->addWidget(readout_);
  connect(open, &QPushButton::clicked, this, &DangerPanel::chooseImage);
  readout_->setText(camera_error +
                    tr("Open a grey-level camera image to see its degree of danger."));
}

void DangerPanel::chooseImage() {
  const QString path = QFileDialog::getOpenFileName(this, tr("Camera image"), {},
                                                    tr("Images (*.png *.pgm *.jpg *.tif *.tiff)"));
  if (!path.isEmpty()) openImage(path);
}

QString DangerPanel::openImage(const QString& path) {
  try {
    return setImage(vision::readGreyImage(path.toStdString()), path);
  } catch (const std::exception& e) {
    readout_->setText(QString::fromStdString(e.what()));
    return readout_->text();
  }
}

QString DangerPanel::setImage(const io::FloatImage& grey, const QString& name) {
  try {
    const auto start = std::chrono::steady_clock::now();
    const auto danger = vision::degreeOfDanger(grey, camera_.camera, camera_.danger);
    route_ = vision::planRoughRoute(danger, camera_.camera);
    sensing_ = vision::planSensing(danger, camera_.camera, *route_);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    view_->picture = blended(grey, danger);
    view_->bands = vision::bandsOf(camera_.camera);
    view_->route = &*route_;
    QString text = tr("%1: %2 x %3, planned in %4 ms. ")
                       .arg(name)
                       .arg(grey.cols)
                       .arg(grey.rows)
                       .arg(ms, 0, 'f', 0);
    if (!route_->found) {
      text += tr("No route: %1.").arg(QString::fromStdString(route_->reason));
    } else {
      text += tr("Route: %1 way areas%2; dangerous above D = %3.")
                  .arg(route_->way_areas.size())
                  .arg(route_->start_moved ? tr(", start moved out of danger") : QString())
                  .arg(route_->threshold, 0, 'f', 2);
      for (const auto& s : sensing_)
        text += tr("\n%1 (%2): %3")
                    .arg(QString::fromStdString(s.band), vision::toString(s.rate),
                         vision::describe(s.action));
    }
    readout_->setText(text);
    view_->update();
    return {};
  } catch (const std::exception& e) {
    route_.reset(), sensing_.clear();
    view_->route = nullptr;
    readout_->setText(QString::fromStdString(e.what()));
    view_->update();
    return readout_->text();
  }
}

QString DangerPanel::readout() const { return readout_->text(); }

}  // namespace ambler::widgets
