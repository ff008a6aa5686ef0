#include "rendering/VtkView.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <deque>
#include <mutex>
#include <utility>

#include <vtkActor.h>
#include <vtkActorCollection.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCellPicker.h>
#include <vtkCommand.h>
#include <vtkDataSet.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkGenericRenderWindowInteractor.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkMapper.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkOpenGLFramebufferObject.h>
#include <vtkProp.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include <QMouseEvent>
#include <QOffscreenSurface>
#include <QOpenGLContext>
#include <QOpenGLExtraFunctions>
#include <QPainter>
#include <QWheelEvent>

namespace ambler::rendering {

// One mouse or wheel event for the interactor, in device pixels with y
// down (the render thread flips it against the window's height).
struct VtkView::Input {
  unsigned long vtk_event = vtkCommand::NoEvent;
  int x = -1, y = -1;  // none for Enter and Leave
  bool ctrl = false, shift = false, alt = false;
  int repeat = 0;
};

// Everything on the render thread: the OpenGL context, VTK's window,
// interactor and scene. Its methods run there, queued by the view.
class VtkView::Renderer : public QObject {
 public:
  Renderer(VtkView* view, QOffscreenSurface* surface) : view_(view), surface_(surface) {
    window_->SetReadyForRendering(false);
    window_->SetFrameBlitModeToNoBlit();
    window_->AddRenderer(renderer_);
    renderer_->SetBackground(0.12, 0.13, 0.15);
    renderer_->SetBackground2(0.30, 0.33, 0.38);
    renderer_->GradientBackgroundOn();
    interactor_->SetRenderWindow(window_);
    vtkNew<vtkInteractorStyleTrackballCamera> style;
    interactor_->SetInteractorStyle(style);
    observe(style.Get(), {vtkCommand::StartInteractionEvent, vtkCommand::EndInteractionEvent});
    observe(window_.Get(), {vtkCommand::WindowMakeCurrentEvent, vtkCommand::WindowIsCurrentEvent,
                            vtkCommand::WindowFrameEvent, vtkCommand::CursorChangedEvent});
  }
  ~Renderer() override { window_->RemoveAllObservers(); }

  void start() {
    context_ = std::make_unique<QOpenGLContext>();
    context_->setFormat(surface_->requestedFormat());
    if (!context_->create() || !context_->makeCurrent(surface_)) {
      qWarning("VtkView: no OpenGL context for the 3-D view");
      context_.reset();
      return;
    }
    window_->SetOwnContext(0);
    window_->SetReadyForRendering(true);
    window_->OpenGLInitContext();
    window_->SetMapped(1);
    interactor_->Initialize();
  }

  // The props' buffers and textures go with the context that made them.
  void stop() {
    if (context_) context_->makeCurrent(surface_);
    renderer_->RemoveAllViewProps();
    detail_.clear();
    if (!context_) return;
    window_->Finalize();
    window_->SetReadyForRendering(false);
    context_->doneCurrent();
    context_.reset();
  }

  void apply(std::vector<SceneChange> changes, bool draw) {
    for (auto& change : changes) change(*renderer_);
    if (draw) ask();
  }

  void resize(int w, int h, double pixel_ratio) {
    pixel_ratio_ = pixel_ratio;
    interactor_->UpdateSize(std::max(1, w), std::max(1, h));
    ask();
  }

  void setShown(bool shown) {
    shown_ = shown;
    if (shown_ && asked_) postRender();
  }

  // Picks the geometry the ray meets, on the CPU: no frame is drawn.
  std::optional<Eigen::Vector3d> pickAt(int x, int y) {
    if (!context_) return std::nullopt;
    const int* size = window_->GetSize();
    vtkNew<vtkCellPicker> picker;
    picker->SetTolerance(1e-4);
    if (!picker->Pick(x, size[1] - 1 - y, 0, renderer_)) return std::nullopt;
    const double* p = picker->GetPickPosition();
    return Eigen::Vector3d(p[0], p[1], p[2]);
  }

  QImage renderNow() {
    if (!context_) return {};
    interactor_->Render();
    framed_ = false;
    return publishFrame();
  }

  // From the GUI thread: successive moves merge into the latest, so a
  // drag never queues more frames than the render thread can draw.
  void post(const Input& input) {
    std::lock_guard lock(inputs_mutex_);
    const bool move = input.vtk_event == vtkCommand::MouseMoveEvent;
    if (move && !inputs_.empty() && inputs_.back().vtk_event == vtkCommand::MouseMoveEvent)
      inputs_.back() = input;
    else
      inputs_.push_back(input);
    if (std::exchange(drain_posted_, true)) return;
    QMetaObject::invokeMethod(
        this, [this] { drain(); }, Qt::QueuedConnection);
  }

  void add(const vtkSmartPointer<vtkProp>& prop) { renderer_->AddViewProp(prop); }

  void addWithStandIn(const vtkSmartPointer<vtkProp>& detailed,
                      const vtkSmartPointer<vtkProp>& stand_in) {
    renderer_->AddViewProp(detailed);
    renderer_->AddViewProp(stand_in);
    detailed->SetVisibility(!moving_);
    stand_in->SetVisibility(moving_);
    detail_.emplace_back(detailed, stand_in);
  }

  void remove(vtkProp* prop) {
    renderer_->RemoveViewProp(prop);
    const auto pair = std::find_if(detail_.begin(), detail_.end(), [prop](const auto& p) {
      return p.first == prop || p.second == prop;
    });
    if (pair == detail_.end()) return;
    renderer_->RemoveViewProp(pair->first == prop ? pair->second : pair->first);
    detail_.erase(pair);
  }

  void clear() {
    renderer_->RemoveAllViewProps();
    detail_.clear();
  }

  void setMoving(bool moving) {
    if (moving == moving_) return;
    moving_ = moving;
    view_->camera_moving_ = moving;
    for (auto& [detailed, stand_in] : detail_) {
      detailed->SetVisibility(!moving);
      stand_in->SetVisibility(moving);
    }
    if (!moving) ask();  // the full detail once the camera rests
  }

 private:
  template <typename Subject>
  void observe(Subject* subject, std::initializer_list<unsigned long> events) {
    auto* callback = vtkCallbackCommand::New();
    callback->SetClientData(this);
    callback->SetCallback([](vtkObject*, unsigned long id, void* self, void* data) {
      static_cast<Renderer*>(self)->onEvent(id, data);
    });
    for (auto id : events) subject->AddObserver(id, callback);
    callback->Delete();
  }

  void onEvent(unsigned long id, void* data) {
    switch (id) {
      case vtkCommand::StartInteractionEvent:
      case vtkCommand::EndInteractionEvent:
        setMoving(id == vtkCommand::StartInteractionEvent);
        break;
      case vtkCommand::WindowMakeCurrentEvent:
        if (context_) context_->makeCurrent(surface_);
        break;
      case vtkCommand::WindowIsCurrentEvent: {
        const auto* current = QOpenGLContext::currentContext();
        *static_cast<bool*>(data) =
            context_ && current == context_.get() && current->surface() == surface_;
        break;
      }
      case vtkCommand::WindowFrameEvent:
        framed_ = true;
        break;
      case vtkCommand::CursorChangedEvent: {
        const bool hand = *static_cast<int*>(data) == VTK_CURSOR_HAND;
        QMetaObject::invokeMethod(
            view_,
            [view = view_, hand] {
              view->setCursor(hand ? Qt::PointingHandCursor : Qt::ArrowCursor);
            },
            Qt::QueuedConnection);
        break;
      }
      default:
        break;
    }
  }

  void ask() {
    asked_ = true;
    if (shown_) postRender();
  }

  void postRender() {
    if (std::exchange(render_posted_, true)) return;
    QMetaObject::invokeMethod(
        this, [this] { renderIfAsked(); }, Qt::QueuedConnection);
  }

  void renderIfAsked() {
    render_posted_ = false;
    if (!asked_ || !shown_) return;
    asked_ = false;
    renderNow();
  }

  void drain() {
    std::deque<Input> inputs;
    {
      std::lock_guard lock(inputs_mutex_);
      inputs.swap(inputs_);
      drain_posted_ = false;
    }
    for (const auto& in : inputs) {
      if (in.x >= 0) {
        interactor_->SetEventInformationFlipY(in.x, in.y, in.ctrl, in.shift);
        interactor_->SetAltKey(in.alt);
      }
      if (in.vtk_event != vtkCommand::MouseMoveEvent) interactor_->SetRepeatCount(in.repeat);
      interactor_->InvokeEvent(in.vtk_event, nullptr);
    }
    // The interactor style rendered (the camera moved): show it.
    if (std::exchange(framed_, false) && context_) publishFrame();
  }

  // VTK's display framebuffer, top row first, opaque.
  QImage readBack() {
    auto* fbo = window_->GetDisplayFramebuffer();
    const int* size = window_->GetSize();
    if (!fbo || size[0] < 1 || size[1] < 1) return {};
    QImage spare;
    QImage& frame = freeBuffer(size[0], size[1], spare);
    fbo->Bind(GL_READ_FRAMEBUFFER);
    fbo->ActivateReadBuffer(0);
    context_->extraFunctions()->glReadPixels(0, 0, size[0], size[1], GL_BGRA, GL_UNSIGNED_BYTE,
                                             frame.bits());
    fbo->UnBind(GL_READ_FRAMEBUFFER);
    // VTK leaves the background's alpha below one; an RGB32 image must be
    // opaque.
    for (int y = 0; y < frame.height(); ++y) {
      auto* row = reinterpret_cast<quint32*>(frame.scanLine(y));
      for (int x = 0; x < frame.width(); ++x) row[x] |= 0xff000000u;
    }
    frame.mirror();
    return frame;
  }

  // A frame buffer of this size that neither the widget nor a frame on its
  // way there holds. A few are reused rather than one allocated per frame,
  // which fragments the heap over a shift. Write through the reference (a
  // copy's bits() would detach); `spare` serves when all kept are taken.
  QImage& freeBuffer(int w, int h, QImage& spare) {
    const QSize size(w, h);
    std::erase_if(buffers_, [&](const QImage& b) {
      return b.size() != size || b.devicePixelRatio() != pixel_ratio_;
    });
    for (QImage& b : buffers_)
      if (b.isDetached()) return b;
    QImage& fresh = buffers_.size() < 3 ? buffers_.emplace_back() : spare;
    fresh = QImage(size, QImage::Format_RGB32);
    fresh.setDevicePixelRatio(pixel_ratio_);
    return fresh;
  }

  // Reads the frame just rendered back and sends it to the widget.
  QImage publishFrame() {
    QImage frame = readBack();
    if (!frame.isNull())
      QMetaObject::invokeMethod(
          view_, [view = view_, frame] { view->showFrame(frame); }, Qt::QueuedConnection);
    return frame;
  }

  VtkView* view_;
  QOffscreenSurface* surface_;
  std::unique_ptr<QOpenGLContext> context_;
  vtkNew<vtkGenericOpenGLRenderWindow> window_;
  vtkNew<vtkGenericRenderWindowInteractor> interactor_;
  vtkNew<vtkRenderer> renderer_;
  std::vector<std::pair<vtkSmartPointer<vtkProp>, vtkSmartPointer<vtkProp>>> detail_;
  std::vector<QImage> buffers_;
  double pixel_ratio_ = 1.0;
  bool moving_ = false, shown_ = false, asked_ = false, render_posted_ = false, framed_ = false;
  std::mutex inputs_mutex_;
  std::deque<Input> inputs_;
  bool drain_posted_ = false;  // guarded by inputs_mutex_
};

namespace {

// The calling thread, and the threads it starts from now on (llvmpipe's
// rasterisers come with the OpenGL context), run at nice 5: on a
// software-rendered console with few cores a frame must not hold back the
// GUI thread's paints and input.
void yieldToTheGuiThread() { setpriority(PRIO_PROCESS, id_t(gettid()), 5); }

}  // namespace

VtkView::VtkView(QWidget* parent) : QWidget(parent), surface_(new QOffscreenSurface) {
  setFocusPolicy(Qt::StrongFocus);
  setMouseTracking(true);
  setMinimumSize(160, 120);
  setAttribute(Qt::WA_OpaquePaintEvent);
  surface_->setFormat(defaultFormat());
  surface_->create();
  renderer_ = std::make_unique<Renderer>(this, surface_);
  renderer_->moveToThread(&thread_);
  thread_.setObjectName("3-D view");
  thread_.start();
  QMetaObject::invokeMethod(renderer_.get(), [r = renderer_.get()] {
    yieldToTheGuiThread();
    r->start();
  });
}

VtkView::~VtkView() {
  QMetaObject::invokeMethod(
      renderer_.get(), [r = renderer_.get()] { r->stop(); }, Qt::BlockingQueuedConnection);
  thread_.quit();
  thread_.wait();
  renderer_.reset();
  delete surface_;
}

void VtkView::edit(SceneChange change) { queued_.push_back(std::move(change)); }

void VtkView::sendQueued(bool draw) {
  QMetaObject::invokeMethod(
      renderer_.get(), [r = renderer_.get(), draw, changes = std::exchange(queued_, {})]() mutable {
        r->apply(std::move(changes), draw);
      });
}

void VtkView::flush() {
  if (!queued_.empty()) sendQueued(false);
}

void VtkView::render() { sendQueued(true); }

void VtkView::inspect(const SceneChange& query) {
  flush();
  QMetaObject::invokeMethod(
      renderer_.get(), [r = renderer_.get(), &query] { r->apply({query}, false); },
      Qt::BlockingQueuedConnection);
}

QImage VtkView::renderedImage() {
  flush();
  QImage frame;
  QMetaObject::invokeMethod(
      renderer_.get(), [r = renderer_.get(), &frame] { frame = r->renderNow(); },
      Qt::BlockingQueuedConnection);
  return frame;
}

void VtkView::add(vtkSmartPointer<vtkProp> prop) {
  edit([r = renderer_.get(), prop = std::move(prop)](vtkRenderer&) { r->add(prop); });
}

void VtkView::addWithStandIn(vtkSmartPointer<vtkProp> detailed, vtkSmartPointer<vtkProp> stand_in) {
  edit([r = renderer_.get(), detailed = std::move(detailed),
        stand_in = std::move(stand_in)](vtkRenderer&) { r->addWithStandIn(detailed, stand_in); });
}

void VtkView::remove(vtkProp* prop) {
  edit([r = renderer_.get(), prop](vtkRenderer&) { r->remove(prop); });
}

void VtkView::clear() {
  edit([r = renderer_.get()](vtkRenderer&) { r->clear(); });
}

void VtkView::setCameraMoving(bool moving) {
  edit([r = renderer_.get(), moving](vtkRenderer&) { r->setMoving(moving); });
  flush();
}

long long VtkView::visibleCells() {
  long long cells = 0;
  inspect([&cells](vtkRenderer& renderer) {
    auto* actors = renderer.GetActors();
    actors->InitTraversal();
    while (vtkActor* actor = actors->GetNextActor())
      if (actor->GetVisibility() && actor->GetMapper() && actor->GetMapper()->GetInput())
        cells += actor->GetMapper()->GetInput()->GetNumberOfCells();
  });
  return cells;
}

std::optional<QPointF> VtkView::widgetPointOf(const Eigen::Vector3d& world) {
  std::optional<QPointF> at;
  const double dpr = devicePixelRatioF();
  inspect([&](vtkRenderer& renderer) {
    const int* size = renderer.GetRenderWindow()->GetSize();
    if (size[0] < 1 || size[1] < 1) return;
    auto* m = renderer.GetActiveCamera()->GetCompositeProjectionTransformMatrix(
        double(size[0]) / size[1], -1, 1);
    const double in[4] = {world.x(), world.y(), world.z(), 1.0};
    double out[4];
    m->MultiplyPoint(in, out);
    if (!(out[3] > 0)) return;
    // Normalised device coordinates to pixels, VTK's rows counted upwards.
    const double x = (out[0] / out[3] + 1) / 2 * size[0];
    const double y = size[1] - 1 - (out[1] / out[3] + 1) / 2 * size[1];
    at = QPointF(x, y) / dpr;
  });
  return at;
}

void VtkView::pick(QPointF position, std::function<void(std::optional<Eigen::Vector3d>)> then) {
  flush();
  const double dpr = devicePixelRatioF();
  QMetaObject::invokeMethod(
      renderer_.get(), [r = renderer_.get(), view = this, x = int(position.x() * dpr),
                        y = int(position.y() * dpr), then = std::move(then)]() mutable {
        const auto point = r->pickAt(x, y);
        QMetaObject::invokeMethod(
            view, [then = std::move(then), point] { then(point); }, Qt::QueuedConnection);
      });
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

void VtkView::showFrame(QImage frame) {
  frame_ = std::move(frame);
  update();
  emit frameRendered();
}

void VtkView::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  if (frame_.isNull()) return painter.fillRect(rect(), QColor(31, 33, 38));
  // A frame drawn before a resize is stretched until the next one comes.
  painter.drawImage(rect(), frame_);
}

void VtkView::resizeEvent(QResizeEvent* e) {
  QWidget::resizeEvent(e);
  const double dpr = devicePixelRatioF();
  QMetaObject::invokeMethod(
      renderer_.get(), [r = renderer_.get(), w = int(width() * dpr), h = int(height() * dpr), dpr] {
        r->resize(w, h, dpr);
      });
}

void VtkView::showEvent(QShowEvent* e) {
  QWidget::showEvent(e);
  flush();
  QMetaObject::invokeMethod(renderer_.get(), [r = renderer_.get()] { r->setShown(true); });
}

void VtkView::hideEvent(QHideEvent* e) {
  QWidget::hideEvent(e);
  QMetaObject::invokeMethod(renderer_.get(), [r = renderer_.get()] { r->setShown(false); });
}

void VtkView::send(const Input& input) { renderer_->post(input); }

bool VtkView::event(QEvent* e) {
  const bool handled = forwardToInteractor(e);
  return QWidget::event(e) || handled;
}

bool VtkView::forwardToInteractor(QEvent* e) {
  const double dpr = devicePixelRatioF();
  auto at = [&](const QPointF& p, Qt::KeyboardModifiers m, unsigned long id) {
    Input in;
    in.vtk_event = id;
    in.x = int(p.x() * dpr), in.y = int(p.y() * dpr);
    in.ctrl = m & Qt::ControlModifier, in.shift = m & Qt::ShiftModifier;
    in.alt = m & Qt::AltModifier;
    return in;
  };
  switch (e->type()) {
    case QEvent::MouseButtonPress:
    case QEvent::MouseButtonRelease:
    case QEvent::MouseButtonDblClick: {
      auto* m = static_cast<QMouseEvent*>(e);
      const bool press = e->type() != QEvent::MouseButtonRelease;
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
      Input in = at(m->position(), m->modifiers(), id);
      in.repeat = e->type() == QEvent::MouseButtonDblClick ? 1 : 0;
      send(in);
      if (m->button() == Qt::LeftButton) {
        if (press) {
          left_pressed_ = m->position();
        } else if (left_pressed_ && (m->position() - *std::exchange(left_pressed_, std::nullopt))
                                            .manhattanLength() <= kClickSlop) {
          emit clicked(m->position());
        }
      }
      return true;
    }
    case QEvent::MouseMove: {
      auto* m = static_cast<QMouseEvent*>(e);
      send(at(m->position(), m->modifiers(), vtkCommand::MouseMoveEvent));
      // A drag that comes back to where it started turned the camera all the same.
      if (left_pressed_ && (m->position() - *left_pressed_).manhattanLength() > kClickSlop)
        left_pressed_.reset();
      return true;
    }
    case QEvent::Wheel: {
      auto* w = static_cast<QWheelEvent*>(e);
      wheel_accumulator_ += w->angleDelta().y();
      // One zoom step per notch (120 units), however the device splits it.
      while (std::abs(wheel_accumulator_) >= 120) {
        const bool forward = wheel_accumulator_ > 0;
        send(
            at(w->position(), w->modifiers(),
               forward ? vtkCommand::MouseWheelForwardEvent : vtkCommand::MouseWheelBackwardEvent));
        wheel_accumulator_ -= forward ? 120 : -120;
      }
      return true;
    }
    case QEvent::Enter:
    case QEvent::Leave: {
      Input in;
      in.vtk_event = e->type() == QEvent::Enter ? vtkCommand::EnterEvent : vtkCommand::LeaveEvent;
      send(in);
      return false;
    }
    default:
      return false;
  }
}

}  // namespace ambler::rendering
