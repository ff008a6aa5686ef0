#pragma once

#include <QWidget>
#include <optional>
#include <utility>
#include <vector>

#include "executive/ReportedStance.h"
#include "executive/TaskTree.h"

class QChart;
class QChartView;
class QLabel;
class QTableWidget;

namespace ambler::widgets {

// The rover as it reports itself (issue 7): body pose, each leg's contact,
// load and foot position, and plots over the mission: when perception,
// planning, the operator and control were busy (cmu-1990 fig. 7), and the
// height and load of each foot. Times on the plots are seconds from `t0`.
class TelemetryPanel : public QWidget {
  Q_OBJECT

 public:
  explicit TelemetryPanel(QWidget* parent = nullptr);

  void setRover(const std::optional<executive::RoverSample>& rover);
  void setModuleTiming(const std::vector<executive::Task>& tasks, double t0, double now_s);
  void setHistory(const std::vector<executive::RoverSample>& history, double t0);
  // A vertical cursor on both plots (a replay's time); none: hidden.
  void setCursor(std::optional<double> time_s_from_t0);

  QTableWidget* legTable() const { return legs_; }
  QChartView* timingView() const { return timing_view_; }
  QChartView* feetView() const { return feet_view_; }
  QChartView* loadsView() const { return loads_view_; }

 private:
  QLabel* pose_;
  QTableWidget* legs_;
  QChartView* timing_view_;
  QChartView* feet_view_;
  QChartView* loads_view_;
};

}  // namespace ambler::widgets
