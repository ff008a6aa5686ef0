#pragma once

#include <QList>
#include <QPointF>
#include <QWidget>
#include <array>
#include <optional>
#include <utility>
#include <vector>

#include "executive/ReportedStance.h"
#include "executive/TaskTree.h"

class QAreaSeries;
class QChart;
class QChartView;
class QLabel;
class QLineSeries;
class QTabWidget;
class QTableWidget;

namespace ambler::widgets {

// The rover as it reports itself: body pose, each leg's contact,
// load and foot position, and plots over the mission: when perception,
// planning, the operator and control were busy (cmu-1990 fig. 7), and the
// height and load of each foot. Times on the plots are seconds from `t0`.
// The series are made once and their points replaced; only the plot in
// view is redrawn, the others when their tab is chosen (a chart's redraw
// costs the GUI thread tens of milliseconds on a long walk).
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
  QChartView* timingView() const { return views_[kTiming]; }
  QChartView* feetView() const { return views_[kFeet]; }
  QChartView* loadsView() const { return views_[kLoads]; }

 private:
  // What one chart shows: its lines' points, the time span and the y range.
  struct PlotData {
    std::vector<QList<QPointF>> lines;
    double span_s = 1.0;
    double y_lo = 0.0, y_hi = 1.0;
    std::optional<double> cursor_s;
    bool stale = false;
  };
  enum Plot { kTiming, kFeet, kLoads, kPlotCount };
  void redrawVisible();
  void redraw(Plot plot);

  QLabel* pose_;
  QTableWidget* legs_;
  std::array<QChartView*, kPlotCount> views_;
  QTabWidget* plots_;
  // Per plot: for the timing plot, each lane's upper then lower line; for
  // the others, one line per leg.
  std::array<std::vector<QLineSeries*>, kPlotCount> series_{};
  std::array<QLineSeries*, kPlotCount> cursors_{};
  std::array<PlotData, kPlotCount> data_{};
};

}  // namespace ambler::widgets
