#pragma once

#include <QWidget>
#include <optional>

#include "widgets/ScanDisplay.h"

class QCheckBox;

namespace ambler::rendering {
class VtkView;
}

namespace ambler::widgets {

// The 3-D view: the ground as a shaded surface coloured by elevation (with
// a colour bar in metres) and the scan's points in the world frame. The
// camera starts behind and above the rover and is kept across new scans.
class TerrainView : public QWidget {
  Q_OBJECT

 public:
  explicit TerrainView(QWidget* parent = nullptr);

  void setScene(const ScanDisplay& display);
  rendering::VtkView* view() const { return view_; }
  QSize sizeHint() const override { return {640, 480}; }

 private:
  void rebuild();

  rendering::VtkView* view_;
  QCheckBox* show_points_;
  std::optional<ScanDisplay> display_;
  bool camera_placed_ = false;
};

}  // namespace ambler::widgets
