// Widget test of the terrain map's cell states as an operator sees them;
// needs a display (xvfb-run).
#include <QApplication>
#include <QImage>
#include <QtTest/QtTest>

#include "tests/widgets/Hover.h"
#include "widgets/MapView.h"

using ambler::GridSpec;
using ambler::terrain::CellState;
using ambler::terrain::ElevationMap;
using ambler::widgets::MapView;

using ambler::test::hover;

class MapViewTest : public QObject {
  Q_OBJECT

 private slots:
  // Ground seen only at a grazing angle has a height but is no foothold:
  // the operator sees its height faded, a state of its own, and the hover
  // readout says so.
  void obliqueGroundIsShownAsSuchOnEveryLayer() {
    // Heights rise with x; the band y in [1, 3) m is oblique, the rest known.
    ElevationMap map(GridSpec::covering({-7, -7, 7, 7}, 0.1));
    const auto& g = map.grid();
    for (int r = 0; r < g.rows; ++r)
      for (int c = 0; c < g.cols; ++c) {
        const auto p = g.cellCenter(r, c);
        const auto state = p.y() >= 1 && p.y() < 3 ? CellState::kOblique : CellState::kKnown;
        map.setHeight(r, c, state, 0.1 * p.x(), 0.01);
      }
    MapView view;
    view.resize(520, 520);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    view.setMap(map);
    auto colourAt = [&](double x, double y) {
      const QImage shot = view.grab().toImage();
      return shot.pixelColor(view.widgetPointOf({x, y}).toPoint());
    };
    const QColor known = colourAt(2.0, -2.0), oblique = colourAt(2.0, 2.0);
    QVERIFY(known != oblique);
    // Faded: the same height, dimmer.
    QVERIFY(oblique.valueF() < 0.8 * known.valueF());
    QCOMPARE(colourAt(-2.0, 2.0) == oblique, false);  // still shows its height

    view.setShown(MapView::Shown::kState);
    const QColor known_state = colourAt(2.0, -2.0), oblique_state = colourAt(2.0, 2.0);
    QVERIFY(known_state != oblique_state);
    QCOMPARE(colourAt(-3.0, 1.5), oblique_state);

    hover(view, view.widgetPointOf({2.0, 2.0}).toPoint());
    QVERIFY(view.readout().contains("not to stand on"));
    QVERIFY(view.readout().contains("sigma 0.010 m"));
    hover(view, view.widgetPointOf({2.0, -2.0}).toPoint());
    QVERIFY(view.readout().contains("elevation"));
    QVERIFY(!view.readout().contains("not to stand on"));
  }

  // Before the first scan (a replay at t = 0) no cell in view has a height:
  // the colour bar shows no scale, rather than 0 to 1 m of nothing.
  void aMapWithoutHeightsShowsNoScale() {
    MapView view;
    view.resize(520, 520);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    auto barShowsTheTopColour = [&] {
      const QImage shot = view.grab().toImage();
      const int right_of_map = int(view.widgetPointOf({7.0, 0.0}).x()) + 4;
      for (int y = 0; y < shot.height(); ++y)
        for (int x = right_of_map; x < shot.width(); ++x) {
          const QColor c = shot.pixelColor(x, y);  // viridis(1): 253, 231, 37
          if (c.red() > 240 && c.green() > 220 && c.blue() < 60) return true;
        }
      return false;
    };
    ElevationMap map(GridSpec::covering({-7, -7, 7, 7}, 0.1));
    view.setMap(map);
    QVERIFY(!barShowsTheTopColour());
    map.setHeight(10, 10, CellState::kKnown, 0.2, 0.01);
    map.setHeight(20, 20, CellState::kKnown, 0.4, 0.01);
    view.setMap(map);
    QVERIFY(barShowsTheTopColour());
  }

  // A click asks to move a leg step's foothold; in a replay, which decides
  // nothing, it does not.
  void aClickMovesTheFootholdUnlessEditingIsOff() {
    MapView view;
    view.resize(520, 520);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    view.setMap(ElevationMap(GridSpec::covering({-7, -7, 7, 7}, 0.1)));
    ambler::executive::StepProposal step;
    step.id = 4;
    step.plan.leg = 2;
    view.setProposal(step);
    QSignalSpy clicked(&view, &MapView::footholdClicked);
    const QPoint at = view.widgetPointOf({1.0, 2.0}).toPoint();
    QTest::mouseClick(&view, Qt::LeftButton, {}, at);
    QCOMPARE(clicked.count(), 1);
    QCOMPARE(clicked.front().at(0).toULongLong(), 4ull);
    QVERIFY(std::abs(clicked.front().at(1).toDouble() - 1.0) < 0.05);
    QVERIFY(std::abs(clicked.front().at(2).toDouble() - 2.0) < 0.05);
    view.setFootholdEditable(false);
    QTest::mouseClick(&view, Qt::LeftButton, {}, at);
    QCOMPARE(clicked.count(), 1);
  }
};

int main(int argc, char** argv) {
  QApplication app(argc, argv);
  MapViewTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "MapViewTest.moc"
