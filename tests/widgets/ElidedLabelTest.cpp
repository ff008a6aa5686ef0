// Widget test of the status line's label: a long message is cut in the
// middle, visibly; needs a display (xvfb-run).
#include <QApplication>
#include <QtTest/QtTest>

#include "widgets/ElidedLabel.h"

using ambler::widgets::ElidedLabel;

class ElidedLabelTest : public QObject {
  Q_OBJECT

 private slots:
  void aLongMessageKeepsItsStartAndItsEnd() {
    ElidedLabel label;
    label.resize(300, 24);
    label.show();
    QVERIFY(QTest::qWaitForWindowExposed(&label));
    const QString message =
        "Connected to built-in simulator on course 1; logging to "
        "/tmp/gs_ScreenFit-MkRkvp/a/long/folder/walk-20261207T024435Z.sqlite";
    label.setText(message);
    const QString shown = label.shownText();
    QVERIFY2(shown.startsWith("Connected"), qPrintable(shown));
    QVERIFY2(shown.endsWith(".sqlite"), qPrintable(shown));
    QVERIFY2(shown.contains(QChar(0x2026)), qPrintable(shown));  // the ellipsis
    QVERIFY(label.fontMetrics().horizontalAdvance(shown) <= label.contentsRect().width());
    QCOMPARE(label.text(), message);  // the whole text stays (tooltips, tests)

    label.setText("Scan 256 x 256");
    QCOMPARE(label.shownText(), QString("Scan 256 x 256"));
  }
};

int main(int argc, char** argv) {
  QApplication app(argc, argv);
  ElidedLabelTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "ElidedLabelTest.moc"
