#pragma once

#include <QColor>
#include <QRectF>
#include <array>
#include <cstdint>

class QPainter;

namespace ambler::widgets {

[[nodiscard]] inline QColor toQColor(const std::array<std::uint8_t, 3>& c) {
  return QColor(c[0], c[1], c[2]);
}

// A vertical viridis bar for values lo..hi (hi at the top), framed, with
// round labels (rendering::colorBarTicks) to its right, in the painter's pen.
void paintColorBar(QPainter& p, const QRectF& bar, double lo, double hi);

}  // namespace ambler::widgets
