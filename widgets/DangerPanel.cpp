#include "widgets/DangerPanel.h"

#include <QFileDialog>
#include <QHBoxLayout>
#include <QLabel>
#include <QPainter>
#include <QPushButton>
#include <QVBoxLayout>
#include <cmath>

#include "rendering/ColorMap.h"
#include "widgets/ColorBar.h"

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
    p.setPen(Qt::white);
    paintColorBar(p, bar, 0.0, 1.0);
    p.drawText(QPointF(bar.left() - 14, bar.top() - 8), tr("D [0-1]"));
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
    : QWidget(parent), view_(new DangerImageView), camera_(new QLabel), readout_(new QLabel) {
  auto* open = new QPushButton(tr("Open camera image…"));
  auto* bar = new QHBoxLayout;
  bar->addWidget(open);
  camera_->setWordWrap(true);
  bar->addWidget(camera_, 1);
  readout_->setWordWrap(true);
  auto* layout = new QVBoxLayout(this);
  layout->addLayout(bar);
  layout->addWidget(view_, 1);
  layout->addWidget(readout_);
  connect(open, &QPushButton::clicked, this, [this] {
    const QString path = QFileDialog::getOpenFileName(
        this, tr("Camera image"), {}, tr("Images (*.png *.pgm *.jpg *.tif *.tiff)"));
    if (!path.isEmpty()) emit imageChosen(path);
  });
  readout_->setText(tr("Open a grey-level camera image to see its degree of danger."));
}

void DangerPanel::setCamera(const QString& summary) { camera_->setText(summary); }

void DangerPanel::showAnalysis(const io::FloatImage& grey, const io::FloatImage& danger,
                               const vision::Bands& bands, const vision::RoughRoute& route,
                               const QString& readout) {
  route_ = route;
  view_->picture = blended(grey, danger);
  view_->bands = bands;
  view_->route = &*route_;
  readout_->setText(readout);
  view_->update();
}

void DangerPanel::showProblem(const QString& why) {
  route_.reset();
  view_->route = nullptr;
  readout_->setText(why);
  view_->update();
}

QString DangerPanel::readout() const { return readout_->text(); }

}  // namespace ambler::widgets
