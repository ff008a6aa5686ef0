#pragma once

#include <QImage>
#include <QWidget>
#include <optional>

#include "sensor/RangeImage.h"

namespace ambler::widgets {

// A range image colour-mapped by range (viridis, robust 2-98 % range) with
// a colour bar in metres and, under the cursor, the pixel's row, column,
// scan angles, range and world coordinates.
class RangeImageView : public QWidget {
  Q_OBJECT

 public:
  explicit RangeImageView(QWidget* parent = nullptr);

  void setImage(const sensor::RangeImage& image);
  void clear();  // back to "No range image yet"
  const std::optional<sensor::RangeImage>& image() const { return image_; }
  const QString& readout() const { return readout_; }
  QSize sizeHint() const override { return {520, 420}; }

  // The image pixel (row, col) under a widget position, if any.
  std::optional<QPoint> pixelAt(const QPointF& widget_pos) const;

 signals:
  void readoutChanged(const QString& text);

 protected:
  void paintEvent(QPaintEvent*) override;
  void mouseMoveEvent(QMouseEvent* e) override;
  void leaveEvent(QEvent*) override;

 private:
  QRectF imageRect() const;
  QRectF colorBarRect() const;
  void setReadout(const QString& text);

  std::optional<sensor::RangeImage> image_;
  QImage colored_;
  double range_lo_ = 0.0, range_hi_ = 1.0;
  QString readout_;
};

}  // namespace ambler::widgets
