#pragma once

#include <vtkSmartPointer.h>

#include <Eigen/Core>
#include <QImage>
#include <QPointF>
#include <QSurfaceFormat>
#include <QThread>
#include <QWidget>
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

class QOffscreenSurface;
class vtkProp;
class vtkRenderer;

namespace ambler::rendering {

// A VTK scene drawn on its own render thread and shown in a plain widget.
// Debian's VTK Qt module is built on Qt5, so this is the project's own
// adapter (STACK.md). VTK renders into its framebuffers in an OpenGL
// context on an offscreen surface owned by the render thread; each frame
// is read back and the widget paints it as an image. The GUI thread never
// waits for a frame (llvmpipe takes 20-30 ms for the walk's map), and no
// OpenGL widget forces the whole window through OpenGL composition.
//
// The scene (renderer, actors, camera) belongs to the render thread: the
// GUI thread builds props and hands them over through edit(), and reads
// the scene only through inspect(). Mouse and wheel events drive a
// trackball camera there.
class VtkView : public QWidget {
  Q_OBJECT

 public:
  using SceneChange = std::function<void(vtkRenderer&)>;

  explicit VtkView(QWidget* parent = nullptr);
  ~VtkView() override;

  // Queues `change` to run on the render thread, in order, before the
  // next frame; render() sends what is queued and asks for a frame.
  void edit(SceneChange change);
  // Sends the queued changes and draws a frame once the render thread is
  // free (frames asked for meanwhile are drawn once).
  void render();
  // Sends the queued changes, runs `query` on the render thread after
  // them and waits for it (tests, measurements, never a workflow).
  void inspect(const SceneChange& query);
  // Sends the queued changes, draws a frame now and returns it (waits for
  // the render thread); the widget shows it like any other frame.
  QImage renderedImage();
  // The frame on screen (may lag the scene by a frame).
  const QImage& shownFrame() const { return frame_; }

  // Adds `prop` to the scene (queued like edit()).
  void add(vtkSmartPointer<vtkProp> prop);
  // Level of detail: `detailed` is drawn while the camera is still and
  // `stand_in` (the same thing decimated) while the mouse moves it, so the
  // view keeps up on software OpenGL (llvmpipe: ~2 fps at 1 M triangles).
  void addWithStandIn(vtkSmartPointer<vtkProp> detailed, vtkSmartPointer<vtkProp> stand_in);
  // Removes `prop` and, when it has one, its stand-in (or the prop it
  // stands in for). `prop` is only compared, never dereferenced here.
  void remove(vtkProp* prop);
  // Removes every prop, stand-ins included.
  void clear();
  bool cameraMoving() const { return camera_moving_; }
  // What the interactor does on a drag (queued); public for timing both
  // levels.
  void setCameraMoving(bool moving);
  // Cells (triangles, points, lines) of the visible actors (waits).
  long long visibleCells();
  // Where `world` is drawn, in widget pixels, by the camera as it is after
  // the queued changes (waits, as inspect() does); none behind the camera.
  std::optional<QPointF> widgetPointOf(const Eigen::Vector3d& world);
  // Where the ray under `position` (widget pixels) first meets a visible,
  // pickable prop, after the queued changes, found on the render thread;
  // `then` gets it, or none where the ray meets nothing, on this thread.
  void pick(QPointF position, std::function<void(std::optional<Eigen::Vector3d>)> then);

  // The surface format VTK needs; set it as the application default before
  // constructing QApplication.
  static QSurfaceFormat defaultFormat();

 signals:
  // A new frame is on screen.
  void frameRendered();
  // A left click that did not turn the camera: released within
  // kClickSlop pixels of where it was pressed.
  void clicked(QPointF position);

 protected:
  void paintEvent(QPaintEvent* e) override;
  void resizeEvent(QResizeEvent* e) override;
  void showEvent(QShowEvent* e) override;
  void hideEvent(QHideEvent* e) override;
  bool event(QEvent* e) override;

 private:
  class Renderer;
  struct Input;
  bool forwardToInteractor(QEvent* e);
  void send(const Input& input);
  void sendQueued(bool draw);
  void flush();
  void showFrame(QImage frame);

  QOffscreenSurface* surface_;
  std::unique_ptr<Renderer> renderer_;
  QThread thread_;
  std::vector<SceneChange> queued_;
  QImage frame_;
  std::atomic<bool> camera_moving_ = false;
  int wheel_accumulator_ = 0;
  static constexpr double kClickSlop = 4.0;  // [px]
  std::optional<QPointF> left_pressed_;
};

}  // namespace ambler::rendering
