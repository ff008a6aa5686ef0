// Widget test of the telemetry plots: points in the plot in view, the
// others drawn when their tab is chosen; needs a display (xvfb-run).
#include <QApplication>
#include <QChart>
#include <QChartView>
#include <QLabel>
#include <QLineSeries>
#include <QTabWidget>
#include <QTableWidget>
#include <QValueAxis>
#include <QtTest/QtTest>
#include <vector>

#include "widgets/TelemetryPanel.h"

using ambler::widgets::TelemetryPanel;

namespace {

// Ten samples 0.5 s apart from t = 100 s; leg k's foot at z = 0.1 k + 0.01 i
// and load (1 + k) kN.
std::vector<ambler::executive::RoverSample> history() {
  std::vector<ambler::executive::RoverSample> samples(10);
  for (int i = 0; i < 10; ++i) {
    samples[std::size_t(i)].time_s = 100.0 + 0.5 * i;
    for (int leg = 0; leg < ambler::gait::kLegCount; ++leg) {
      samples[std::size_t(i)].stance.feet[std::size_t(leg)] = {0, 0, 0.1 * leg + 0.01 * i};
      samples[std::size_t(i)].force_n[std::size_t(leg)] = 1000.0 * (1 + leg);
    }
  }
  return samples;
}

// The plot's line of leg `leg` (named "leg N").
QLineSeries* legLine(QChartView* view, int leg) {
  for (auto* s : view->chart()->series())
    if (s->name() == QString("leg %1").arg(leg)) return qobject_cast<QLineSeries*>(s);
  return nullptr;
}

QTabWidget* tabsOf(QChartView* view) {
  for (QWidget* w = view; w; w = w->parentWidget())
    if (auto* tabs = qobject_cast<QTabWidget*>(w)) return tabs;
  return nullptr;
}

}  // namespace

class TelemetryPanelTest : public QObject {
  Q_OBJECT

 private slots:
  void aPlotOutOfViewIsDrawnWhenItsTabIsChosen() {
    TelemetryPanel panel;
    panel.resize(1000, 400);
    panel.show();
    QVERIFY(QTest::qWaitForWindowExposed(&panel));
    auto* tabs = tabsOf(panel.feetView());
    QVERIFY(tabs);
    tabs->setCurrentWidget(panel.feetView());
    panel.setHistory(history(), 100.0);

    // In view: every leg's line, in seconds from t0 and metres.
    for (int leg = 0; leg < ambler::gait::kLegCount; ++leg) {
      auto* line = legLine(panel.feetView(), leg);
      QVERIFY(line);
      QCOMPARE(line->count(), 10);
      QCOMPARE(line->at(9).x(), 4.5);
      QVERIFY(std::abs(line->at(9).y() - (0.1 * leg + 0.09)) < 1e-12);
    }
    // Time runs to the next round figure above the last sample (4.5 s).
    auto* x = qobject_cast<QValueAxis*>(panel.feetView()->chart()->axes(Qt::Horizontal).front());
    QCOMPARE(x->min(), 0.0);
    QCOMPARE(x->max(), 5.0);
    QCOMPARE(x->labelFormat(), QString("%.1f"));
    auto* y = qobject_cast<QValueAxis*>(panel.feetView()->chart()->axes(Qt::Vertical).front());
    QVERIFY(std::abs(y->min() - (0.0 - 0.05)) < 1e-9);
    QVERIFY(std::abs(y->max() - (0.59 + 0.05)) < 1e-9);

    // Out of view: not drawn yet; drawn, in kN, once chosen.
    QCOMPARE(legLine(panel.loadsView(), 2)->count(), 0);
    tabs->setCurrentWidget(panel.loadsView());
    QCOMPARE(legLine(panel.loadsView(), 2)->count(), 10);
    QCOMPARE(legLine(panel.loadsView(), 2)->at(0).y(), 3.0);
    panel.grab().save(QCoreApplication::applicationDirPath() + "/screenshot-telemetry-loads.png");

    // A refresh replaces the points: the same series, not new ones.
    const auto series_before = panel.loadsView()->chart()->series().size();
    auto shorter = history();
    shorter.resize(4);
    panel.setHistory(shorter, 100.0);
    QCOMPARE(panel.loadsView()->chart()->series().size(), series_before);
    QCOMPARE(legLine(panel.loadsView(), 2)->count(), 4);
  }

  // Under a second of history the time axis spans one second (its range
  // from the start) and still labels tenths.
  void aFirstSecondIsLabelledInTenths() {
    TelemetryPanel panel;
    panel.show();
    QVERIFY(QTest::qWaitForWindowExposed(&panel));
    tabsOf(panel.feetView())->setCurrentWidget(panel.feetView());
    auto samples = history();
    samples.resize(2);
    panel.setHistory(samples, 100.0);
    auto* x = qobject_cast<QValueAxis*>(panel.feetView()->chart()->axes(Qt::Horizontal).front());
    QCOMPARE(x->max(), 1.0);
    QCOMPARE(x->labelFormat(), QString("%.1f"));
  }

  // A body or foot a hair below zero reads 0, not -0.000.
  void valuesThatRoundToZeroHaveNoSign() {
    TelemetryPanel panel;
    ambler::executive::RoverSample rover;
    rover.stance.body.xy = {-2e-5, 0.5};
    rover.stance.body.heading_rad = -1e-4;
    rover.stance.feet[0] = {-0.0004, -1.25, -0.05};
    panel.setRover(rover);
    QString pose;
    for (const auto* label : panel.findChildren<QLabel*>())
      if (label->text().startsWith("Body x")) pose = label->text();
    QCOMPARE(pose, QString("Body x 0.000 m, y 0.500 m, link plane z 2.400 m, heading 0.0°"));
    auto* legs = panel.findChild<QTableWidget*>();
    QVERIFY(legs);
    QCOMPARE(legs->item(0, 3)->text(), QString("0.000"));
    QCOMPARE(legs->item(0, 4)->text(), QString("-1.250"));
  }

  // While the rover says a move is under way, its last pose is where the
  // move began, and the panel says so.
  void aMoveUnderWayIsShownWithThePose() {
    TelemetryPanel panel;
    ambler::executive::RoverSample rover;
    rover.stance.body.xy = {1.0, 2.0};
    rover.moving = true;
    panel.setRover(rover);
    QString pose;
    for (const auto* label : panel.findChildren<QLabel*>())
      if (label->text().startsWith("Body x")) pose = label->text();
    QCOMPARE(pose, QString("Body x 1.000 m, y 2.000 m, link plane z 2.400 m, heading 0.0° · "
                           "moving: where the move under way began"));
  }
};

int main(int argc, char** argv) {
  QApplication app(argc, argv);
  TelemetryPanelTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "TelemetryPanelTest.moc"
