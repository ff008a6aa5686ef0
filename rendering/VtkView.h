#pragma once

#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkGenericRenderWindowInteractor.h>
#include <vtkNew.h>
#include <vtkRenderer.h>

#include <QOpenGLWidget>
#include <QSurface>
#include <QSurfaceFormat>
#include <utility>
#include <vector>

class vtkProp;

namespace ambler::rendering {

// A VTK render window inside a Qt6 widget. Debian's VTK Qt module is built
// on Qt5, so this is the project's own adapter (STACK.md): VTK renders into
// its own framebuffer in Qt's context, and paintGL blits it into the
// widget's framebuffer. Mouse and wheel events drive a trackball camera.
class VtkView : public QOpenGLWidget {
  Q_OBJECT

 public:
  explicit VtkView(QWidget* parent = nullptr);
  ~VtkView() override;

  vtkRenderer* renderer() const;
  vtkGenericOpenGLRenderWindow* renderWindow() const;

  // Schedules a VTK render of the scene (after changing actors or camera).
  void render();

  // Level of detail: `detailed` is drawn while the camera is still and
  // `stand_in` (the same thing decimated) while the mouse moves it, so the
  // view keeps up on software OpenGL (llvmpipe: ~2 fps at 1 M triangles).
  // Both join the renderer.
  void addWithStandIn(vtkProp* detailed, vtkProp* stand_in);
  // Removes `prop` and, when it has one, its stand-in (or the prop it
  // stands in for).
  void remove(vtkProp* prop);
  // Removes every prop, stand-ins included.
  void clear();
  bool cameraMoving() const { return camera_moving_; }
  // What the interactor does on a drag; public for timing both levels.
  void setCameraMoving(bool moving);
  // Cells (triangles, points, lines) of the visible actors.
  long long visibleCells() const;

  // The surface format VTK needs; set it as the application default before
  // constructing QApplication.
  static QSurfaceFormat defaultFormat();

 signals:
  // A frame reached the widget's framebuffer.
  void frameRendered();

 protected:
  void initializeGL() override;
  void resizeGL(int w, int h) override;
  void paintGL() override;
  bool event(QEvent* e) override;

 private:
  void onRenderWindowEvent(vtkObject* caller, unsigned long event_id, void* call_data);
  void releaseGraphics();
  bool forwardToInteractor(QEvent* e);

  vtkNew<vtkGenericOpenGLRenderWindow> window_;
  vtkNew<vtkGenericRenderWindowInteractor> interactor_;
  vtkNew<vtkRenderer> renderer_;
  QSurface* surface_ = nullptr;
  QMetaObject::Connection context_connection_;
  bool render_pending_ = true;
  bool in_paint_ = false;
  int wheel_accumulator_ = 0;
  std::vector<std::pair<vtkProp*, vtkProp*>> detail_;  // owned by the renderer
  bool camera_moving_ = false;
};

}  // namespace ambler::rendering
