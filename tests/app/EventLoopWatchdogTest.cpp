// The GUI's stall meter on a known stall: an event loop blocked for
// 150 ms once must read a worst stall of at least that less one period,
// counted over 50 ms, and quantiles in order. (No upper bound: a loaded
// machine may stall the loop more, never less.)
#include <QCoreApplication>
#include <QThread>
#include <QTimer>
#include <QtTest/QtTest>

#include "app/gs/EventLoopWatchdog.h"

class EventLoopWatchdogTest : public QObject {
  Q_OBJECT

 private slots:
  void aBlockedLoopIsMeasured() {
    ambler::gs::EventLoopWatchdog watchdog(5);
    watchdog.start();
    QTimer::singleShot(200, this, [] { QThread::msleep(150); });
    QTest::qWait(600);
    watchdog.stop();
    const auto s = watchdog.summary();
    QVERIFY2(s.ticks > 20, qPrintable(QString::number(s.ticks)));
    QVERIFY2(s.max_ms >= 140.0, qPrintable(QString::number(s.max_ms)));
    QVERIFY(s.over_50ms >= 1);
    QVERIFY(s.over_20ms >= s.over_50ms);
    QVERIFY(s.p50_ms <= s.p99_ms && s.p99_ms <= s.max_ms);
  }

  void nothingMeasuredIsZero() {
    const ambler::gs::EventLoopWatchdog idle;
    const auto s = idle.summary();
    QCOMPARE(s.ticks, 0L);
    QCOMPARE(s.max_ms, 0.0);
  }
};

QTEST_MAIN(EventLoopWatchdogTest)
#include "EventLoopWatchdogTest.moc"
