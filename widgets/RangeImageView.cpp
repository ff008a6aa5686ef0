#include "widgets/RangeImageView.h"

#include <QMouseEvent>
#include <QPainter>
#include <algorithm>
#include <cmath>

#include "rendering/ColorMap.h"
#include "widgets/ColorBar.h"

namespace ambler::widgets {

namespace {

constexpr int kMargin = 8;
constexpr int kBarWidth = 18;
constexpr int kBarLabelSpace = 56;
constexpr int kReadoutHeight = 22;
constexpr double kRadToDeg = 180.0 / M_PI;

// The 2nd and 98th percentiles of the valid ranges: one far outlier must
// not flatten the colours of the rest.
std::pair<double, double> robustRange(const sensor::RangeImage& image) {
  std::vector<float> v;
  for (float r : image.range)
    if (std::isfinite(r) && r > 0.0f) v.push_back(r);
  if (v.empty()) return {0.0, 1.0};
  auto at = [&](double q) {
    auto it = v.begin() + std::ptrdiff_t(q * double(v.size() - 1));
    std::nth_element(v.begin(), it, v.end());
    return double(*it);
  };
  const double lo = at(0.02), hi = at(0.98);
  return {lo, hi > lo ? hi : lo + 1.0};
}

}  // namespace

RangeImageView::RangeImageView(QWidget* parent) : QWidget(parent) {
  setMouseTracking(true);
  setMinimumSize(280, 200);
  setAttribute(Qt::WA_OpaquePaintEvent);
}

void RangeImageView::setImage(const sensor::RangeImage& image) {
  image_ = image;
  std::tie(range_lo_, range_hi_) = robustRange(image);
  colored_ = QImage(image.cols(), image.rows(), QImage::Format_RGB32);
  for (int r = 0; r < image.rows(); ++r)
    for (int c = 0; c < image.cols(); ++c) {
      const auto rgb =
          image.hasReturn(r, c)
              ? rendering::viridis((image.at(r, c) - range_lo_) / (range_hi_ - range_lo_))
              : rendering::kNoDataColor;
      colored_.setPixel(c, r, qRgb(rgb[0], rgb[1], rgb[2]));
    }
  update();
}

void RangeImageView::clear() {
  image_.reset();
  colored_ = QImage();
  setReadout({});
  update();
}

QRectF RangeImageView::imageRect() const {
  const QRectF area(kMargin, kMargin, width() - 3 * kMargin - kBarWidth - kBarLabelSpace,
                    height() - 2 * kMargin - kReadoutHeight);
  if (colored_.isNull() || area.width() <= 0 || area.height() <= 0) return area;
  const double scale = std::min(area.width() / colored_.width(), area.height() / colored_.height());
  const QSizeF size(colored_.width() * scale, colored_.height() * scale);
  return QRectF(area.topLeft() +
                    QPointF((area.width() - size.width()) / 2, (area.height() - size.height()) / 2),
                size);
}

QRectF RangeImageView::colorBarRect() const {
  const QRectF img = imageRect();
  return QRectF(width() - kMargin - kBarLabelSpace - kBarWidth, img.top() + 20, kBarWidth,
                std::max(40.0, img.height() - 40));
}

std::optional<QPoint> RangeImageView::pixelAt(const QPointF& pos) const {
  const QRectF rect = imageRect();
  if (!image_ || !rect.contains(pos)) return std::nullopt;
  const int c = std::clamp(int((pos.x() - rect.left()) / rect.width() * image_->cols()), 0,
                           image_->cols() - 1);
  const int r = std::clamp(int((pos.y() - rect.top()) / rect.height() * image_->rows()), 0,
                           image_->rows() - 1);
  return QPoint(c, r);
}

void RangeImageView::paintEvent(QPaintEvent*) {
  QPainter p(this);
  p.fillRect(rect(), palette().window());
  if (colored_.isNull()) {
    p.drawText(rect(), Qt::AlignCenter, tr("No range image yet"));
    return;
  }
  p.drawImage(imageRect(), colored_);

  // Colour bar: far ranges at the top, like the image's upper rows.
  const QRectF bar = colorBarRect();
  p.setPen(palette().windowText().color());
  paintColorBar(p, bar, range_lo_, range_hi_);
  p.drawText(QRectF(bar.left() - 30, bar.top() - 20, kBarWidth + kBarLabelSpace + 30, 16),
             Qt::AlignCenter, tr("Range [m]"));
  const QRectF no_data(bar.left(), bar.bottom() + 8, kBarWidth, 10);
  p.fillRect(no_data, toQColor(rendering::kNoDataColor));
  p.drawText(QPointF(no_data.right() + 4, no_data.bottom()), tr("none"));

  p.drawText(
      QRectF(kMargin, height() - kMargin - kReadoutHeight, width() - 2 * kMargin, kReadoutHeight),
      Qt::AlignLeft | Qt::AlignVCenter,
      readout_.isEmpty() ? tr("Hover over the image for row, column, angles and range") : readout_);
}

void RangeImageView::mouseMoveEvent(QMouseEvent* e) {
  const auto pixel = pixelAt(e->position());
  if (!pixel) return setReadout({});
  const int r = pixel->y(), c = pixel->x();
  const auto& g = image_->geometry;
  QString text = tr("row %1, col %2 | phi %3°, theta %4° | ")
                     .arg(r)
                     .arg(c)
                     .arg(g.phi(r) * kRadToDeg, 0, 'f', 2)
                     .arg(g.theta(c) * kRadToDeg, 0, 'f', 2);
  if (image_->hasReturn(r, c)) {
    const auto w = image_->pointInWorld(r, c);
    text += tr("rho %1 m | world x %2, y %3, z %4 m")
                .arg(image_->at(r, c), 0, 'f', 3)
                .arg(w.x(), 0, 'f', 2)
                .arg(w.y(), 0, 'f', 2)
                .arg(w.z(), 0, 'f', 2);
  } else {
    text += tr("no return");
  }
  setReadout(text);
}

void RangeImageView::leaveEvent(QEvent*) { setReadout({}); }

void RangeImageView::setReadout(const QString& text) {
  if (text == readout_) return;
  readout_ = text;
  emit readoutChanged(readout_);
  update();
}

}  // namespace ambler::widgets
