#include "app/gs/DangerController.h"

#include <chrono>

#include "core/Resources.h"
#include "vision/DangerMap.h"
#include "widgets/DangerPanel.h"

namespace ambler::gs {

DangerController::DangerController(widgets::DangerPanel& panel, QObject* parent)
    : QObject(parent), panel_(panel) {
  QString camera_error;
  try {
    camera_ = vision::readCameraFile(findResource("config/camera.json"));
  } catch (const std::exception& e) {  // the built-in defaults, and say so
    camera_error = tr("Camera file unusable (%1); using the built-in camera. ").arg(e.what());
  }
  panel_.setCamera(camera_error + tr("Camera: %1 rows, axis %2° from the vertical, %3° field of "
                                     "view, %4 m up (config/camera.json)")
                                      .arg(camera_.camera.rows)
                                      .arg(camera_.camera.alpha_deg)
                                      .arg(camera_.camera.beta_deg)
                                      .arg(camera_.camera.height_m));
  connect(&panel_, &widgets::DangerPanel::imageChosen, this, [this](const QString& path) {
    [[maybe_unused]] const auto opened = open(path);  // a refusal is shown in the panel
  });
}

Refusal DangerController::refuse(const std::string& why) {
  route_.reset(), sensing_.clear();
  panel_.showProblem(QString::fromStdString(why));
  return Refusal::because(why);
}

Refusal DangerController::open(const QString& path) {
  try {
    return analyse(vision::readGreyImage(path.toStdString()), path);
  } catch (const std::exception& e) {
    return refuse(e.what());
  }
}

Refusal DangerController::analyse(const io::FloatImage& grey, const QString& name) {
  try {
    const auto start = std::chrono::steady_clock::now();
    const auto danger = vision::degreeOfDanger(grey, camera_.camera, camera_.danger);
    route_ = vision::planRoughRoute(danger, camera_.camera);
    sensing_ = vision::planSensing(danger, camera_.camera, *route_);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    QString text = tr("%1: %2 x %3, planned in %4 ms. ")
                       .arg(name)
                       .arg(grey.cols)
                       .arg(grey.rows)
                       .arg(ms, 0, 'f', 0);
    if (!route_->found) {
      text += tr("No route: %1.").arg(QString::fromStdString(route_->reason));
    } else {
      text += tr("Route: %1 way areas%2; dangerous above D = %3.")
                  .arg(route_->way_areas.size())
                  .arg(route_->start_moved ? tr(", start moved out of danger") : QString())
                  .arg(route_->threshold, 0, 'f', 2);
      for (const auto& s : sensing_)
        text += tr("\n%1 (%2): %3")
                    .arg(QString::fromStdString(s.band), vision::toString(s.rate),
                         vision::describe(s.action));
    }
    panel_.showAnalysis(grey, danger, vision::bandsOf(camera_.camera), *route_, text);
    return {};
  } catch (const std::exception& e) {
    return refuse(e.what());
  }
}

}  // namespace ambler::gs
