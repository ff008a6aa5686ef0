#include "widgets/ColorBar.h"

#include <QPainter>

#include "rendering/ColorMap.h"

namespace ambler::widgets {

void paintColorBar(QPainter& p, const QRectF& bar, double lo, double hi) {
  const QPen pen = p.pen();
  for (int y = 0; y < int(bar.height()); ++y) {
    p.setPen(toQColor(rendering::viridis(1.0 - y / bar.height())));
    p.drawLine(QPointF(bar.left(), bar.top() + y), QPointF(bar.right(), bar.top() + y));
  }
  p.setPen(pen);
  p.setBrush(Qt::NoBrush);
  p.drawRect(bar);
  const auto ticks = rendering::colorBarTicks(lo, hi);
  for (const double value : ticks.values) {
    const double y =
        hi > lo ? bar.top() + (hi - value) / (hi - lo) * bar.height() : bar.center().y();
    p.drawLine(QPointF(bar.right(), y), QPointF(bar.right() + 4, y));
    p.drawText(QPointF(bar.right() + 7, y + 4), QString::number(value, 'f', ticks.decimals));
  }
}

}  // namespace ambler::widgets
