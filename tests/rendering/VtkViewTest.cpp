// Widget test of the Qt6 <-> VTK adapter; needs a display (xvfb-run).
#include <vtkCamera.h>
#include <vtkRenderer.h>

#include <QApplication>
#include <QColor>
#include <QImage>
#include <QMouseEvent>
#include <QSet>
#include <QSurfaceFormat>
#include <QtTest/QtTest>
#include <array>
#include <cmath>
#include <memory>

#include "rendering/SceneBuilders.h"
#include "rendering/VtkView.h"

using ambler::rendering::VtkView;

namespace {

// z = 0.5 sin(x) cos(y) on a 6 m x 6 m grid at 10 cm.
void addWavySurface(VtkView& view) {
  const ambler::GridSpec grid{-3.0, -3.0, 0.1, 60, 60};
  ambler::io::FloatImage z(grid.rows, grid.cols);
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) {
      const auto p = grid.cellCenter(r, c);
      z(r, c) = float(0.5 * std::sin(p.x()) * std::cos(p.y()));
    }
  auto table = ambler::rendering::makeViridisTable(-0.5, 0.5);
  view.add(ambler::rendering::makeHeightSurface(grid, z, table));
  view.add(ambler::rendering::makeColorBar(table, "Elevation [m]"));
  view.edit([](vtkRenderer& renderer) { renderer.ResetCamera(); });
  view.render();
}

struct CameraPose {
  std::array<double, 3> position{};
  double distance = 0.0;
};

CameraPose cameraOf(VtkView& view) {
  CameraPose pose;
  view.inspect([&pose](vtkRenderer& renderer) {
    auto* camera = renderer.GetActiveCamera();
    camera->GetPosition(pose.position.data());
    pose.distance = camera->GetDistance();
  });
  return pose;
}

void sendMouse(QWidget& w, QEvent::Type type, QPointF pos, Qt::MouseButtons buttons) {
  QMouseEvent e(type, pos, w.mapToGlobal(pos),
                type == QEvent::MouseMove ? Qt::NoButton : Qt::LeftButton, buttons, Qt::NoModifier);
  QApplication::sendEvent(&w, &e);
}

QImage renderedImage(VtkView& view) { return view.renderedImage(); }

// Pixels of the viridis surface or colour bar (the background is grey).
int colouredPixels(const QImage& image) {
  int coloured = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      coloured += image.pixelColor(x, y).hsvSaturation() > 100;
  return coloured;
}

}  // namespace

class VtkViewTest : public QObject {
  Q_OBJECT

  std::unique_ptr<VtkView> view_;

 private slots:
  // Each test gets a fresh, shown 400 x 300 view of the wavy surface.
  void init() {
    view_ = std::make_unique<VtkView>();
    view_->resize(400, 300);
    addWavySurface(*view_);
    view_->show();
    QVERIFY(QTest::qWaitForWindowExposed(view_.get()));
  }
  void cleanup() { view_.reset(); }

  void rendersAColouredSurface() {
    const QImage image = renderedImage(*view_);
    QCOMPARE(image.width(), 400);
    image.save(QCoreApplication::applicationDirPath() + "/screenshot-vtkview.png");

    // The background is a grey-blue gradient (low saturation); the surface
    // is viridis-coloured (saturated, many hues).
    int saturated = 0;
    QSet<int> hues;
    for (int y = 0; y < image.height(); ++y)
      for (int x = 0; x < image.width(); ++x) {
        const QColor c = image.pixelColor(x, y);
        if (c.hsvSaturation() > 100) {
          ++saturated;
          hues.insert(c.hsvHue() / 10);
        }
      }
    const double fraction = double(saturated) / (image.width() * image.height());
    QVERIFY2(fraction > 0.15, qPrintable(QString("only %1 of pixels coloured").arg(fraction)));
    QVERIFY2(hues.size() >= 5, qPrintable(QString("only %1 hue bands").arg(hues.size())));
  }

  // Frames come from the render thread by themselves: a scene change and
  // a resize reach the widget with nobody waiting for them.
  void aSceneChangeReachesTheScreenOnItsOwn() {
    VtkView& view = *view_;
    QTRY_VERIFY(!view.shownFrame().isNull());
    const int coloured_before = colouredPixels(view.shownFrame());
    QVERIFY2(coloured_before > 1000, qPrintable(QString::number(coloured_before)));
    view.clear();
    view.render();
    QTRY_COMPARE(colouredPixels(view.shownFrame()), 0);
    view.resize(300, 200);
    const double dpr = view.devicePixelRatioF();
    QTRY_COMPARE(view.shownFrame().size(), QSize(int(300 * dpr), int(200 * dpr)));
  }

  void mouseDragMovesTheCamera() {
    VtkView& view = *view_;
    const QImage before = renderedImage(view);
    const CameraPose pose0 = cameraOf(view);
    const auto& p0 = pose0.position;
    const double distance0 = pose0.distance;

    sendMouse(view, QEvent::MouseButtonPress, {200, 150}, Qt::LeftButton);
    for (int dx = 10; dx <= 120; dx += 10)
      sendMouse(view, QEvent::MouseMove, {200.0 + dx, 150.0}, Qt::LeftButton);
    sendMouse(view, QEvent::MouseButtonRelease, {320, 150}, Qt::NoButton);

    const CameraPose pose1 = cameraOf(view);
    const auto& p1 = pose1.position;
    const double moved = std::hypot(p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]);
    QVERIFY2(moved > 0.1 * distance0, qPrintable(QString("camera moved %1 m").arg(moved)));
    // Trackball rotation orbits the focal point at constant distance.
    QVERIFY(std::abs(pose1.distance - distance0) < 1e-6 * distance0);
    // The drag's frames reach the widget without anyone asking for them.
    QTRY_VERIFY(view.shownFrame() != before);
  }

  // While the mouse drags the camera the thinned stand-in is drawn; the
  // full surface is back once the button is released.
  void aStandInIsDrawnWhileTheCameraMoves() {
    VtkView& view = *view_;
    view.clear();
    const ambler::GridSpec grid{-3.0, -3.0, 0.01, 600, 600};
    ambler::io::FloatImage z(grid.rows, grid.cols);
    for (int r = 0; r < grid.rows; ++r)
      for (int c = 0; c < grid.cols; ++c) z(r, c) = float(0.01 * r - 0.02 * c);
    const auto [thin_grid, thin] = ambler::rendering::thinned(grid, z, 20000);
    QVERIFY(thin_grid.cellCount() <= 20000);
    QVERIFY(thin_grid.cellCount() > 10000);
    // Kept cells sit where they were, with their heights.
    const double k = thin_grid.resolution / grid.resolution;
    QCOMPARE(k, 5.0);
    const auto centre = thin_grid.cellCenter(7, 9);
    QVERIFY((centre - grid.cellCenter(35, 45)).norm() < 1e-9);
    QCOMPARE(thin(7, 9), z(35, 45));

    auto table = ambler::rendering::makeViridisTable(-12, 6);
    auto full = ambler::rendering::makeHeightSurface(grid, z, table);
    auto stand_in = ambler::rendering::makeHeightSurface(thin_grid, thin, table);
    view.addWithStandIn(full, stand_in);
    view.edit([](vtkRenderer& renderer) { renderer.ResetCamera(); });
    // Which of the two the scene draws, read on the render thread.
    const auto drawn = [&] {
      std::pair<bool, bool> visible;
      view.inspect([&](vtkRenderer&) {
        visible = {bool(full->GetVisibility()), bool(stand_in->GetVisibility())};
      });
      return visible;
    };
    QCOMPARE(drawn(), std::make_pair(true, false));
    sendMouse(view, QEvent::MouseButtonPress, {200, 150}, Qt::LeftButton);
    sendMouse(view, QEvent::MouseMove, {230, 150}, Qt::LeftButton);
    QCOMPARE(drawn(), std::make_pair(false, true));
    QVERIFY(view.cameraMoving());
    sendMouse(view, QEvent::MouseButtonRelease, {230, 150}, Qt::NoButton);
    QCOMPARE(drawn(), std::make_pair(true, false));
    QVERIFY(!view.cameraMoving());
  }
};

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(VtkView::defaultFormat());
  QApplication app(argc, argv);
  VtkViewTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "VtkViewTest.moc"
