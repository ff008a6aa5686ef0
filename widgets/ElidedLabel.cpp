#include "widgets/ElidedLabel.h"

#include <QPainter>

namespace ambler::widgets {

QString ElidedLabel::shownText() const {
  return fontMetrics().elidedText(text(), Qt::ElideMiddle, contentsRect().width());
}

void ElidedLabel::paintEvent(QPaintEvent*) {
  QPainter p(this);
  p.setPen(palette().color(foregroundRole()));
  p.drawText(contentsRect(), int(alignment()) | Qt::TextSingleLine, shownText());
}

}  // namespace ambler::widgets
