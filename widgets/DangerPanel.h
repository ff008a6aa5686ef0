#pragma once

#include <QWidget>
#include <optional>

#include "io/Image.h"
#include "vision/RoughRoute.h"
#include "vision/VisionFiles.h"

class QLabel;

namespace ambler::widgets {

class DangerImageView;

// ejiri for the operator: a grey-level camera image with its degree of
// danger D over it (viridis, with a colour bar), the distance bands, the
// rough route with its start, Way Areas and destination, and the sensing
// plan along it.
class DangerPanel : public QWidget {
  Q_OBJECT

 public:
  explicit DangerPanel(QWidget* parent = nullptr);

  // Reads the image (PNG, PGM, JPEG, TIFF) and plans on it; empty when
  // done, else why not (also shown in the panel).
  QString openImage(const QString& path);
  QString setImage(const io::FloatImage& grey, const QString& name);

  const std::optional<vision::RoughRoute>& route() const { return route_; }
  const std::vector<vision::SensingStep>& sensing() const { return sensing_; }
  QString readout() const;

 private:
  void chooseImage();

  vision::CameraFile camera_;
  DangerImageView* view_;
  QLabel* readout_;
  std::optional<vision::RoughRoute> route_;
  std::vector<vision::SensingStep> sensing_;
};

}  // namespace ambler::widgets
