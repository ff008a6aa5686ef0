#pragma once

#include <QObject>
#include <optional>
#include <vector>

#include "core/Refusal.h"
#include "io/Image.h"
#include "vision/RoughRoute.h"
#include "vision/VisionFiles.h"

namespace ambler::widgets {
class DangerPanel;
}

namespace ambler::gs {

// The Danger map tab's work (ejiri 1990): reads the camera configuration,
// and for each grey image computes the degree of danger, the rough route
// and the sensing plan, and gives the panel what to draw. 8.5 ms for a
// 640 x 480 image (README), so it runs where it is called.
class DangerController : public QObject {
  Q_OBJECT

 public:
  explicit DangerController(widgets::DangerPanel& panel, QObject* parent = nullptr);

  // Reads the image (PNG, PGM, JPEG, TIFF) and analyses it; a refusal is
  // also shown in the panel.
  Refusal open(const QString& path);
  Refusal analyse(const io::FloatImage& grey, const QString& name);

  const std::optional<vision::RoughRoute>& route() const { return route_; }
  const std::vector<vision::SensingStep>& sensing() const { return sensing_; }

 private:
  Refusal refuse(const std::string& why);

  widgets::DangerPanel& panel_;
  vision::CameraFile camera_;
  std::optional<vision::RoughRoute> route_;
  std::vector<vision::SensingStep> sensing_;
};

}  // namespace ambler::gs
