// The console on the operator's screen: run once per screen
// (ctest starts it under its own Xvfb of that size, see tests/CMakeLists.txt).
// The window opens inside the available screen, Approve, Reject and HOLD are
// wholly visible with a step waiting, View > Reset layout brings a hidden
// dock back, and what the screen shows is saved as a screenshot.
#include <QAction>
#include <QApplication>
#include <QCheckBox>
#include <QDir>
#include <QDockWidget>
#include <QMenuBar>
#include <QPushButton>
#include <QScreen>
#include <QSettings>
#include <QStandardPaths>
#include <QStatusBar>
#include <QTemporaryDir>
#include <QToolBar>
#include <QToolButton>
#include <QtTest/QtTest>

#include "app/gs/GroundStation.h"
#include "core/Resources.h"
#include "gait/RoverConfig.h"
#include "tests/app/TestStation.h"
#include "widgets/StepApprovalPanel.h"

namespace {

using ambler::gs::test::options;

QString describe(const QRect& r) {
  return QString("%1 x %2 at (%3, %4)").arg(r.width()).arg(r.height()).arg(r.x()).arg(r.y());
}

// Why `widget` is not wholly on `screen` and unclipped, or empty.
QString offScreen(const QWidget* widget, const QRect& screen) {
  if (!widget->isVisible()) return widget->objectName() + " is hidden";
  const QRect global(widget->mapToGlobal(QPoint(0, 0)), widget->size());
  if (!screen.contains(global))
    return QString("%1 lies at %2, outside the screen's %3")
        .arg(widget->objectName(), describe(global), describe(screen));
  if (widget->visibleRegion().boundingRect() != widget->rect())
    return QString("%1 is clipped to %2 of %3")
        .arg(widget->objectName(), describe(widget->visibleRegion().boundingRect()),
             describe(widget->rect()));
  return {};
}

}  // namespace

class ScreenFitTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() { QStandardPaths::setTestModeEnabled(true); }

  void theApprovalControlsAreOnScreenWithAStepWaiting() {
    QTemporaryDir logs;
    ambler::gs::GroundStation station(options(logs.path()));
    auto& window = station.window();
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    const QRect screen = window.screen()->availableGeometry();
    auto& panel = *window.approvalPanel();
    station.startWalk(1);
    QTRY_VERIFY_WITH_TIMEOUT(panel.approveButton()->isEnabled(), 60000);
    QTest::qWait(500);  // let the docks settle

    const QRect frame = window.frameGeometry();
    QVERIFY2(
        screen.contains(frame),
        qPrintable(
            QString("the window is %1 on a screen of %2").arg(describe(frame), describe(screen))));
    panel.approveButton()->setObjectName("Approve");
    panel.rejectButton()->setObjectName("Reject");
    auto* hold = window.findChild<QToolBar*>("scan-toolbar")->widgetForAction(window.holdAction());
    hold->setObjectName("HOLD");
    window.statusBar()->setObjectName("status bar");
    for (const QWidget* w :
         {static_cast<QWidget*>(panel.approveButton()), static_cast<QWidget*>(panel.rejectButton()),
          hold, static_cast<QWidget*>(window.statusBar())}) {
      const QString why = offScreen(w, screen);
      QVERIFY2(why.isEmpty(), qPrintable(why));
    }

    const QString name =
        QString("screen-%1x%2.png")
            .arg(window.screen()->geometry().width() * window.screen()->devicePixelRatio())
            .arg(window.screen()->geometry().height() * window.screen()->devicePixelRatio());
    const QDir dir(AMBLER_SCREENSHOT_DIR);
    QVERIFY(dir.mkpath("."));
    QVERIFY(window.screen()->grabWindow(0).save(dir.filePath(name)));
  }

  void aLayoutSavedOnALargerScreenIsFittedToThisOne() {
    QTemporaryDir logs;
    {
      ambler::widgets::MainWindow big;
      big.show();
      QVERIFY(QTest::qWaitForWindowExposed(&big));
      big.setGeometry(QRect(QPoint(0, 0), big.screen()->availableGeometry().size() * 2));
      QSettings().setValue("main/geometry", big.saveGeometry());
    }
    ambler::gs::GroundStation station(options(logs.path()));
    auto& window = station.window();
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    const QRect screen = window.screen()->availableGeometry();
    QVERIFY2(screen.contains(window.frameGeometry()),
             qPrintable(QString("the window is %1 on a screen of %2")
                            .arg(describe(window.frameGeometry()), describe(screen))));
    QSettings().remove("main/geometry");
  }

  // What the operator reaches for stays where it is: the docks and the views
  // keep their geometry from 1 s after the first scan is shown through a
  // walk's first steps and the auto-approve switch.
  void theLayoutDoesNotMoveUnderTheOperatorsHand() {
    QTemporaryDir logs;
    ambler::gs::GroundStation station(options(logs.path()));
    auto& window = station.window();
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    QSignalSpy scanned(&window, &ambler::widgets::MainWindow::scanShown);
    emit window.scanRequested(1);
    QVERIFY(scanned.wait(30000));
    QTest::qWait(1000);
    const auto layout = [&] {
      QStringList parts;
      for (const QWidget* w : window.findChildren<QDockWidget*>())
        parts << w->objectName() + " " + describe(w->geometry());
      parts << "central " + describe(window.centralWidget()->geometry());
      parts << "window " + describe(window.geometry());
      return parts.join("; ");
    };
    const QString before = layout();
    station.startWalk(3);
    window.approvalPanel()->autoApproveSwitch()->setChecked(true);
    QTRY_VERIFY_WITH_TIMEOUT(station.session()->state().steps_done >= 2, 60000);
    window.approvalPanel()->autoApproveSwitch()->setChecked(false);
    QTest::qWait(500);
    QCOMPARE(layout(), before);
  }

  void resetLayoutBringsBackAHiddenDock() {
    QTemporaryDir logs;
    ambler::gs::GroundStation station(options(logs.path()));
    auto& window = station.window();
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    auto* dock = window.findChild<QDockWidget*>("step-approval-dock");
    QVERIFY(dock);
    dock->hide();
    QAction* reset = nullptr;
    for (auto* action : window.menuBar()->findChildren<QAction*>())
      if (action->text().remove('&') == "Reset layout") reset = action;
    QVERIFY2(reset, "View > Reset layout is missing");
    reset->trigger();
    QTRY_VERIFY(dock->isVisible());
    QVERIFY(!dock->isFloating());
    QCOMPARE(window.dockWidgetArea(dock), Qt::RightDockWidgetArea);
  }
};

QTEST_MAIN(ScreenFitTest)
#include "ScreenFitTest.moc"
