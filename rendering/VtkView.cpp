#include "rendering/VtkView.h"

#include <algorithm>

#include <vtkActor.h>
#include <vtkActorCollection.h>
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkDataSet.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkMapper.h>
#include <vtkOpenGLFramebufferObject.h>
#include <vtkProp.h>

#include <QEvent>
#include <QMouseEvent>
#include <QOpenGLContext>
#include <QOpenGLExtraFunctions>
#include <QWheelEvent>

namespace ambler::rendering {

VtkView::VtkView(QWidget* parent) : QOpenGLWidget(parent) {
  setFocusPolicy(Qt::StrongFocus);
  setMouseTracking(true);
  setMinimumSize(160, 120);

  window_->SetReadyForRendering(false);
  window_->SetFrameBlitModeToNoBlit();
  window_->AddRenderer(renderer_);
  renderer_->SetBackground(0.12, 0.13, 0.15);
  renderer_->SetBackground2(0.30, 0.33, 0.38);
  renderer_->GradientBackgroundOn();

  interactor_->SetRenderWindow(window_);
  vtkNew<vtkInteractorStyleTrackballCamera> style;
  interactor_->SetInteractorStyle(style);
  interactor_->Initialize();
  auto* moving = vtkCallbackCommand::New();
  moving->SetClientData(this);
  moving->SetCallback([](vtkObject*, unsigned long id, void* self, void*) {
    static_cast<VtkView*>(self)->setCameraMoving(id == vtkCommand::StartInteractionEvent);
  });
  style->AddObserver(vtkCommand::StartInteractionEvent, moving);
  style->AddObserver(vtkCommand::EndInteractionEvent, moving);
  moving->Delete();

  auto* callback = vtkCallbackCommand::New();
  callback->SetClientData(this);
  callback->SetCallback([](vtkObject* caller, unsigned long id, void* self, void* data) {
    static_cast<VtkView*>(self)->onRenderWindowEvent(caller, id, data);
  });
  for (auto id : {vtkCommand::WindowMakeCurrentEvent, vtkCommand::WindowIsCurrentEvent,
                  vtkCommand::WindowFrameEvent, vtkCommand::CursorChangedEvent})
    window_->AddObserver(id, callback);
  callback->Delete();
}

VtkView::~VtkView() {
  // Disconnect first: finalising through aboutToBeDestroyed during our own
  // destruction would touch a half-destroyed widget (crash on exit).
  disconnect(context_connection_);
  makeCurrent();
  releaseGraphics();
  doneCurrent();
  window_->RemoveAllObservers();
}

vtkRenderer* VtkView::renderer() const { return renderer_.Get(); }

vtkGenericOpenGLRenderWindow* VtkView::renderWindow() const { return window_.Get(); }

void VtkView::render() {
  render_pending_ = true;
  update();
}

void VtkView::addWithStandIn(vtkProp* detailed, vtkProp* stand_in) {
  renderer_->AddViewProp(detailed);
  renderer_->AddViewProp(stand_in);
  detailed->SetVisibility(!camera_moving_);
  stand_in->SetVisibility(camera_moving_);
  detail_.emplace_back(detailed, stand_in);
}

void VtkView::remove(vtkProp* prop) {
  renderer_->RemoveViewProp(prop);
  const auto pair = std::find_if(detail_.begin(), detail_.end(), [prop](const auto& p) {
    return p.first == prop || p.second == prop;
  });
  if (pair == detail_.end()) return;
  renderer_->RemoveViewProp(pair->first == prop ? pair->second : pair->first);
  detail_.erase(pair);
}

void VtkView::clear() {
  renderer_->RemoveAllViewProps();
  detail_.clear();
}

long long VtkView::visibleCells() const {
  long long cells = 0;
  auto* actors = renderer_->GetActors();
  actors->InitTraversal();
  while (vtkActor* actor = actors->GetNextActor())
    if (actor->GetVisibility() && actor->GetMapper() && actor->GetMapper()->GetInput())
      cells += actor->GetMapper()->GetInput()->GetNumberOfCells();
  return cells;
}

void VtkView::setCameraMoving(bool moving) {
  if (moving == camera_moving_) return;
  camera_moving_ = moving;
  for (auto& [detailed, stand_in] : detail_) {
    detailed->SetVisibility(!moving);
    stand_in->SetVisibility(moving);
  }
  if (!moving) render();  // the full detail once the camera rests
}

QSurfaceFormat VtkView::defaultFormat() {
  QSurfaceFormat format;
  format.setRenderableType(QSurfaceFormat::OpenGL);
  format.setVersion(3, 2);
  format.setProfile(QSurfaceFormat::CoreProfile);
  format.setSwapBehavior(QSurfaceFormat::DoubleBuffer);
  format.setRedBufferSize(8);
  format.setGreenBufferSize(8);
  format.setBlueBufferSize(8);
  format.setAlphaBufferSize(8);
  format.setDepthBufferSize(24);
  format.setStencilBufferSize(0);
  format.setSamples(0);
  return format;
}

void VtkView::initializeGL() {
  surface_ = context()->surface();
  context_connection_ = connect(
      context(), &QOpenGLContext::aboutToBeDestroyed, this, [this] { releaseGraphics(); },
      Qt::DirectConnection);
  window_->SetOwnContext(0);
  window_->SetReadyForRendering(true);
  window_->OpenGLInitContext();
  window_->SetMapped(1);
  render_pending_ = true;
}

void VtkView::releaseGraphics() {
  if (!surface_) return;
  window_->Finalize();
  window_->SetReadyForRendering(false);
  surface_ = nullptr;
}

void VtkView::resizeGL(int w, int h) {
  const double dpr = devicePixelRatioF();
  interactor_->UpdateSize(int(w * dpr), int(h * dpr));
  render_pending_ = true;
}

void VtkView::paintGL() {
  if (!surface_) return;
  in_paint_ = true;
  if (render_pending_) interactor_->Render();
  render_pending_ = false;
  in_paint_ = false;

  // Blit VTK's display framebuffer into the widget's framebuffer.
  auto* f = context()->extraFunctions();
  f->glBindFramebuffer(GL_DRAW_FRAMEBUFFER, defaultFramebufferObject());
  const GLenum attachment = GL_COLOR_ATTACHMENT0;
  f->glDrawBuffers(1, &attachment);
  const int* size = window_->GetRenderFramebuffer()->GetLastSize();
  window_->BlitDisplayFramebuffer(0, 0, 0, size[0], size[1], 0, 0, size[0], size[1],
                                  GL_COLOR_BUFFER_BIT, GL_LINEAR);
  // Opaque alpha, or Mesa blends the widget with what lies behind it.
  f->glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_TRUE);
  f->glClearColor(0, 0, 0, 1);
  f->glClear(GL_COLOR_BUFFER_BIT);
  f->glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  emit frameRendered();
}

void VtkView::onRenderWindowEvent(vtkObject*, unsigned long event_id, void* call_data) {
  switch (event_id) {
    case vtkCommand::WindowMakeCurrentEvent:
      // Not QOpenGLWidget::makeCurrent(): that re-binds Qt's framebuffer
      // while VTK builds its own (black image, GL_INVALID_FRAMEBUFFER_OPERATION).
      if (surface_) context()->makeCurrent(surface_);
      break;
    case vtkCommand::WindowIsCurrentEvent: {
      const auto* current = QOpenGLContext::currentContext();
      *static_cast<bool*>(call_data) =
          surface_ && current == context() && current->surface() == surface_;
      break;
    }
    case vtkCommand::WindowFrameEvent:
      // VTK rendered outside paintGL (e.g. the camera moved): show it.
      render_pending_ = false;
      if (!in_paint_) update();
      break;
    case vtkCommand::CursorChangedEvent:
      setCursor(*static_cast<int*>(call_data) == VTK_CURSOR_HAND ? Qt::PointingHandCursor
                                                                 : Qt::ArrowCursor);
      break;
    default:
      break;
  }
}

bool VtkView::event(QEvent* e) {
  const bool handled = forwardToInteractor(e);
  return QOpenGLWidget::event(e) || handled;
}

bool VtkView::forwardToInteractor(QEvent* e) {
  const double dpr = devicePixelRatioF();
  auto set_position = [&](const QPointF& p, Qt::KeyboardModifiers m) {
    interactor_->SetEventInformationFlipY(int(p.x() * dpr), int(p.y() * dpr),
                                          (m & Qt::ControlModifier) ? 1 : 0,
                                          (m & Qt::ShiftModifier) ? 1 : 0);
    interactor_->SetAltKey((m & Qt::AltModifier) ? 1 : 0);
  };
  switch (e->type()) {
    case QEvent::MouseButtonPress:
    case QEvent::MouseButtonRelease:
    case QEvent::MouseButtonDblClick: {
      auto* m = static_cast<QMouseEvent*>(e);
      set_position(m->position(), m->modifiers());
      const bool press = e->type() != QEvent::MouseButtonRelease;
      if (press) interactor_->SetRepeatCount(e->type() == QEvent::MouseButtonDblClick ? 1 : 0);
      unsigned long id = 0;
      switch (m->button()) {
        case Qt::LeftButton:
          id = press ? vtkCommand::LeftButtonPressEvent : vtkCommand::LeftButtonReleaseEvent;
          break;
        case Qt::MiddleButton:
          id = press ? vtkCommand::MiddleButtonPressEvent : vtkCommand::MiddleButtonReleaseEvent;
          break;
        case Qt::RightButton:
          id = press ? vtkCommand::RightButtonPressEvent : vtkCommand::RightButtonReleaseEvent;
          break;
        default:
          return false;
      }
      interactor_->InvokeEvent(id, e);
      return true;
    }
    case QEvent::MouseMove: {
      auto* m = static_cast<QMouseEvent*>(e);
      set_position(m->position(), m->modifiers());
      interactor_->InvokeEvent(vtkCommand::MouseMoveEvent, e);
      return true;
    }
    case QEvent::Wheel: {
      auto* w = static_cast<QWheelEvent*>(e);
      set_position(w->position(), w->modifiers());
      wheel_accumulator_ += w->angleDelta().y();
      // One zoom step per notch (120 units), however the device splits it.
      while (std::abs(wheel_accumulator_) >= 120) {
        const bool forward = wheel_accumulator_ > 0;
        interactor_->InvokeEvent(
            forward ? vtkCommand::MouseWheelForwardEvent : vtkCommand::MouseWheelBackwardEvent, e);
        wheel_accumulator_ -= forward ? 120 : -120;
      }
      return true;
    }
    case QEvent::Enter:
      interactor_->InvokeEvent(vtkCommand::EnterEvent, e);
      return false;
    case QEvent::Leave:
      interactor_->InvokeEvent(vtkCommand::LeaveEvent, e);
      return false;
    default:
      return false;
  }
}

}  // namespace ambler::rendering
