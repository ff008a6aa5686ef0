#pragma once

#include <QWidget>
#include <optional>

#include "io/Image.h"
#include "vision/DangerMap.h"
#include "vision/RoughRoute.h"

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

  void setCamera(const QString& summary);
  // The image with its degree of danger over it, the distance bands, the
  // rough route and what the analysis found, in sentences.
  void showAnalysis(const io::FloatImage& grey, const io::FloatImage& danger,
                    const vision::Bands& bands, const vision::RoughRoute& route,
                    const QString& readout);
  // No analysis to show, and why.
  void showProblem(const QString& why);

  const std::optional<vision::RoughRoute>& route() const { return route_; }
  QString readout() const;

 signals:
  void imageChosen(const QString& path);

 private:
  DangerImageView* view_;
  QLabel* camera_;
  QLabel* readout_;
  std::optional<vision::RoughRoute> route_;
};

}  // namespace ambler::widgets
