// Widget test of the 3-D view as an operator sees it; needs a display
// (xvfb-run).
#include <QApplication>
#include <QCheckBox>
#include <QImage>
#include <QSurfaceFormat>
#include <QToolTip>
#include <QtTest/QtTest>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "rendering/SceneBuilders.h"
#include "rendering/VtkView.h"
#include "widgets/TerrainView.h"

using ambler::GridSpec;
using ambler::rendering::VtkView;
using ambler::terrain::CellState;
using ambler::terrain::ElevationMap;
using ambler::widgets::RoverDisplay;
using ambler::widgets::TerrainView;

namespace {

int distance(const QColor& a, const QColor& b) {
  return std::abs(a.red() - b.red()) + std::abs(a.green() - b.green()) +
         std::abs(a.blue() - b.blue());
}

// Pixels that drawing something over `under` changed (`drawn`), and, within
// its footprint (a drawn pixel at most 2 px away), those of the surface
// (saturated viridis, unlike the grey-blue background) and of them the
// ones left as they were.
struct Coverage {
  int drawn = 0, surface = 0, surface_seen = 0;
};

Coverage coverage(const QImage& under, const QImage& over) {
  const int w = over.width(), h = over.height();
  Coverage out;
  std::vector<char> changed(std::size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      out.drawn += changed[std::size_t(y) * w + x] =
          distance(over.pixelColor(x, y), under.pixelColor(x, y)) >= 30;
  for (int y = 2; y < h - 2; ++y)
    for (int x = 2; x < w - 2; ++x) {
      if (under.pixelColor(x, y).hsvSaturationF() < 0.3) continue;
      bool near_drawn = false;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) near_drawn |= changed[std::size_t(y + dy) * w + x + dx];
      if (!near_drawn) continue;
      ++out.surface;
      out.surface_seen += !changed[std::size_t(y) * w + x];
    }
  return out;
}

// Heights rise with x (5 cm a metre): the map's colours run across the
// colour bar.
ElevationMap risingWithX() {
  ElevationMap map(GridSpec::covering({-6, -2, 6, 14}, 0.1));
  const auto& g = map.grid();
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c)
      map.setHeight(r, c, CellState::kKnown, 0.05 * g.cellCenter(r, c).x(), 0.01);
  return map;
}

// Known ground in a fan 53 degrees wide, 4-11 m ahead of the rover at the
// origin (facing +y), as a walk's first scan leaves its map.
ElevationMap scannedFan() {
  ElevationMap map(GridSpec::covering({-10, -8, 10, 45}, 0.1));
  const auto& g = map.grid();
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      const auto p = g.cellCenter(r, c);
      if (p.y() >= 4 && p.y() <= 11 && std::abs(p.x()) <= 0.5 * p.y())
        map.setHeight(r, c, CellState::kKnown, 0.05 * p.x(), 0.01);
    }
  return map;
}

}  // namespace

class TerrainViewTest : public QObject {
  Q_OBJECT

 private slots:
  // A walk's registered scans lie over its map in the 3-D view. The
  // operator sees the scan's points and, between them, the map's colours,
  // which the colour bar explains: dots 2 px wide hid most of the surface
  // under one orange.
  void registeredScansLetTheMapShowThrough() {
    const ElevationMap map = risingWithX();
    std::vector<Eigen::Vector3d> scan;
    for (double y = 2.0; y < 8.0; y += 0.1)  // 10 cm apart, as a walking scan 5-10 m out
      for (double x = -3.0; x < 3.0; x += 0.1) scan.push_back({x, y, 0.05 * x + 0.01});

    TerrainView view;
    view.resize(640, 480);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    view.setMap(map);
    view.setRover(RoverDisplay{}, {}, std::nullopt);  // places the camera behind the rover
    view.setRegisteredScans({scan});
    auto* points = view.findChild<QCheckBox*>();
    QVERIFY(points && points->text().contains("Scan points"));

    points->setChecked(false);
    QTest::qWait(50);  // the rebuild is queued
    const QImage map_only = view.view()->renderedImage();
    points->setChecked(true);
    QTest::qWait(50);
    const QImage with_scan = view.view()->renderedImage();
    QCOMPARE(with_scan.size(), map_only.size());

    const Coverage seen = coverage(map_only, with_scan);
    QVERIFY2(seen.surface > 10000, qPrintable(QString::number(seen.surface)));
    // The scan is there to see...
    QVERIFY2(seen.drawn > 3000, qPrintable(QString::number(seen.drawn)));
    // ...and much of the map between its points (59 % here; 27 % under
    // dots 2 px wide).
    QVERIFY2(seen.surface_seen > 0.45 * seen.surface,
             qPrintable(QString("%1 of %2 pixels").arg(seen.surface_seen).arg(seen.surface)));
  }

  // With the terrain mesh and path shown, a click on the ground in the 3-D
  // view picks the point under it (the path's start or goal): through a
  // foot drawn over it, which is not ground. A drag turns the camera and
  // picks nothing; with the mesh hidden a click picks nothing, and before
  // there is a mesh it says why.
  void aClickOnTheGroundPicksThePointUnderIt() {
    const ElevationMap map = risingWithX();
    const Eigen::Vector3d target(1.0, 6.0, 0.05);
    RoverDisplay rover;
    rover.stance.feet[0] = target;  // a foot's sphere, 0.15 m, over the point
    TerrainView view;
    view.resize(640, 480);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    view.setMap(map);
    view.setRover(rover, {}, std::nullopt);
    QTest::qWait(50);  // the rebuild is queued
    view.view()->renderedImage();
    QSignalSpy picked(&view, &TerrainView::groundPicked);
    const auto shown = view.view()->widgetPointOf(target);
    QVERIFY(shown && view.view()->rect().contains(shown->toPoint()));
    const QPoint at = shown->toPoint();
    // Without a mesh there is no path to start: the click asks for one
    // and says so.
    QSignalSpy wanted(&view, &TerrainView::meshWanted);
    QTest::mouseClick(view.view(), Qt::LeftButton, {}, at);
    QTRY_VERIFY(QToolTip::text().contains("No terrain mesh yet: building it"));
    QCOMPARE(wanted.count(), 1);
    QVERIFY(!picked.wait(300));
    view.setMeshOverlay({{{0, 0, 0}, {1, 0, 0}}}, {});  // any mesh
    QTest::mouseClick(view.view(), Qt::LeftButton, {}, at);
    QVERIFY(picked.wait(5000));
    const auto xy = picked.takeFirst().at(0).value<Eigen::Vector2d>();
    // Within a pixel's rounding (a pixel spans about 8 cm of ground there);
    // the foot's sphere would put it 0.14 m nearer the camera.
    QVERIFY2((xy - target.head<2>()).norm() < 0.07,
             qPrintable(QString("picked %1, %2").arg(xy.x()).arg(xy.y())));

    QCheckBox* mesh = nullptr;
    for (auto* box : view.findChildren<QCheckBox*>())
      if (box->text().contains("Terrain mesh")) mesh = box;
    QVERIFY(mesh);
    mesh->setChecked(false);
    QTest::mouseClick(view.view(), Qt::LeftButton, {}, at);
    QVERIFY(!picked.wait(500));
    mesh->setChecked(true);

    QTest::mousePress(view.view(), Qt::LeftButton, {}, at);
    QTest::mouseMove(view.view(), at + QPoint(40, 0));
    QTest::mouseRelease(view.view(), Qt::LeftButton, {}, at + QPoint(2, 0));
    QVERIFY(!picked.wait(500));
  }

  // The colour bar stands in the right fifth of the 3-D view; the camera
  // behind the rover keeps the scanned ground left of it, and in view, in a
  // square view, a 4:3 one and a wide one (a 1366 x 768 screen's view).
  void theScannedGroundStaysLeftOfTheColourBar() {
    const ElevationMap map = scannedFan();
    for (const QSize size : {QSize(480, 480), QSize(640, 480), QSize(480, 340), QSize(800, 400)}) {
      TerrainView view;
      view.resize(size.width(), size.height() + 30);  // the check boxes below the view
      view.show();
      QVERIFY(QTest::qWaitForWindowExposed(&view));
      view.setMap(map);
      view.setRover(RoverDisplay{}, {}, std::nullopt);
      QTest::qWait(50);  // the rebuild is queued
      view.view()->renderedImage();
      const double bar_left = ambler::rendering::kColorBarLeft * view.view()->width();
      for (const double y : {4.0, 11.0})
        for (const double side : {-1.0, 1.0}) {
          const Eigen::Vector3d corner(side * 0.5 * y, y, 0.05 * side * 0.5 * y);
          const auto shown = view.view()->widgetPointOf(corner);
          QVERIFY(shown);
          const QString where =
              QString("view %1 x %2: corner (%3, %4) at x = %5 px, bar from %6 px")
                  .arg(view.view()->width())
                  .arg(view.view()->height())
                  .arg(corner.x())
                  .arg(corner.y())
                  .arg(shown->x())
                  .arg(bar_left);
          QVERIFY2(shown->x() > 0 && shown->x() < bar_left, qPrintable(where));
          QVERIFY2(shown->y() > 0 && shown->y() < view.view()->height(), qPrintable(where));
        }
    }
  }

  // Ground with no known height (a scene over a terrain model's no-data)
  // draws no surface and no colour bar: the bar's range came out NaN, and
  // its ticks read -nan in white. One known height brings the bar back.
  void groundWithNoKnownHeightDrawsNoColourBar() {
    ambler::widgets::ScanDisplay display;
    display.ground_grid = GridSpec::covering({-6, -2, 6, 14}, 0.1);
    display.ground =
        ambler::io::FloatImage(display.ground_grid.rows, display.ground_grid.cols, NAN);
    TerrainView view;
    view.resize(640, 480);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    struct Drawn {
      int white = 0, coloured = 0;
    };
    auto drawn = [&] {
      QTest::qWait(50);  // the rebuild is queued
      const QImage image = view.view()->renderedImage();
      Drawn d;
      for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) {
          const QColor c = image.pixelColor(x, y);
          d.white += c.lightness() > 200 && c.hsvSaturationF() < 0.1;
          d.coloured += c.hsvSaturationF() >= 0.3;
        }
      return d;
    };
    view.setScene(display);
    const Drawn empty = drawn();
    QCOMPARE(empty.white, 0);
    QCOMPARE(empty.coloured, 0);
    display.ground(40, 60) = 0.2f;
    display.ground(41, 60) = 0.3f;
    view.setScene(display);
    const Drawn two = drawn();
    QVERIFY2(two.white > 50, qPrintable(QString::number(two.white)));  // the title and ticks
    QVERIFY2(two.coloured > 1000, qPrintable(QString::number(two.coloured)));
  }
};

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(VtkView::defaultFormat());
  QApplication app(argc, argv);
  TerrainViewTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "TerrainViewTest.moc"
