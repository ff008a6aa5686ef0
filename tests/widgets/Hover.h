#pragma once

#include <QApplication>
#include <QMouseEvent>
#include <QWidget>

namespace ambler::test {

// The pointer over `at` in `widget`, as a mouse move event delivered at
// once. QTest::mouseMove moves the display's one pointer, which the other
// widget tests that ctest runs beside this one on the same X server move
// too: a hover readout would follow their moves.
inline void hover(QWidget& widget, const QPoint& at) {
  QMouseEvent move(QEvent::MouseMove, at, widget.mapToGlobal(at), Qt::NoButton, Qt::NoButton,
                   Qt::NoModifier);
  QApplication::sendEvent(&widget, &move);
}

}  // namespace ambler::test
