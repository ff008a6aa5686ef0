#pragma once

#include <QMainWindow>

#include "core/Refusal.h"
#include "widgets/ScanDisplay.h"
#include "widgets/WalkCommandBar.h"

class QLabel;
class QProgressBar;
class QSpinBox;
class QAction;

namespace ambler::widgets {

class CommandLogView;
class RangeImageView;
class StepApprovalPanel;
class MapView;
class TelemetryPanel;
class TerrainView;
class TimelineBar;

// The operator's main window: the range image and the terrain map beside
// the 3-D view; docks for the step approval, the rover's telemetry, the
// event and command table and (in a replay) the timeline, each restored
// where the operator left it. It asks for work through its signals and
// shows what it is given; where data comes from (simulator, rover, log) is
// not its business. It exports what it shows: map layers as TIFF, plots as
// PNG, the table as CSV.
class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit MainWindow(QWidget* parent = nullptr);

  void showScan(const ScanDisplay& display);
  void showError(const QString& message);
  void setBusy(const QString& what);  // empty: idle
  // The status bar's message, until the next one.
  void setStatus(const QString& text);
  const QString& statusText() const { return status_text_; }
  quint64 seed() const;
  void setSeed(quint64 seed);

  RangeImageView* rangeView() const { return range_view_; }
  TerrainView* terrainView() const { return terrain_view_; }
  QAction* scanAction() const { return scan_action_; }
  QAction* walkAction() const { return walk_action_; }
  WalkCommandBar* walkCommandBar() const { return walk_command_; }
  QAction* holdAction() const { return hold_action_; }
  StepApprovalPanel* approvalPanel() const { return approval_; }
  MapView* mapView() const { return map_view_; }
  class SamplingPanel* samplingPanel() const {
    return sampling_;
  }
  void showSamplingView();
  class DangerPanel* dangerPanel() const {
    return danger_panel_;
  }
  class TerrainMeshPanel* meshPanel() const {
    return mesh_panel_;
  }
  void showMeshView();
  void showDangerView();
  TelemetryPanel* telemetry() const { return telemetry_; }
  CommandLogView* commandLog() const { return command_log_; }
  TimelineBar* timeline() const { return timeline_; }
  class QToolBar* timelineBar() const {
    return timeline_bar_;
  }
  QProgressBar* progress() const { return progress_; }
  // A replay of `what` (shown in the title, the timeline shown), or live.
  void setReplay(const QString& what);
  // Each is refused, with what went wrong, when the files were not written.
  Refusal exportMapLayers(const QString& dir) const;
  Refusal exportPlots(const QString& dir) const;
  Refusal exportTable(const QString& file) const;
  // Brings the terrain map to the front (a replay opened).
  void showMapView();
  // "simulator in this process: last data 0.4 s ago"; stale shows in red.
  void setLinkStatus(const QString& text, bool stale);
  // Which authority action makes sense now: asking when another console
  // (or none) holds it, handing over to `asking` when this one does.
  void setAuthority(bool this_console_holds, const QString& asking);
  QAction* requestAuthorityAction() const { return request_authority_; }
  QAction* handOverAction() const { return hand_over_; }

 signals:
  void scanRequested(quint64 seed);
  // The Walk action, with the steps and path beside it.
  void walkRequested(const ambler::widgets::WalkCommand& command);
  // The operator pressed Hold: stop the rover now.
  void holdRequested();
  // Command authority: ask for it, or give it to the console asking.
  void authorityRequested();
  void handOverRequested();
  void scanShown();  // showScan() has put a scan in the views
  void errorShown(const QString& message);  // showError(), before its dialog opens
  void connectRequested();
  void openLogRequested(const QString& path);

 protected:
  void closeEvent(QCloseEvent* e) override;
  void showEvent(QShowEvent* e) override;

 private:
  RangeImageView* range_view_;
  TerrainView* terrain_view_;
  QSpinBox* seed_box_;
  QAction* scan_action_;
  WalkCommandBar* walk_command_;
  QAction* walk_action_;
  QAction* hold_action_;
  QAction* request_authority_ = nullptr;
  QAction* hand_over_ = nullptr;
  StepApprovalPanel* approval_;
  MapView* map_view_;
  class SamplingPanel* sampling_;
  class TerrainMeshPanel* mesh_panel_;
  class DangerPanel* danger_panel_;
  class QTabWidget* views_;
  QLabel* status_;
  QString status_text_;
  QLabel* link_status_;
  QProgressBar* progress_;
  TelemetryPanel* telemetry_;
  CommandLogView* command_log_;
  TimelineBar* timeline_;
  class QToolBar* timeline_bar_;

  QByteArray default_state_;   // the docks as built, for View > Reset layout
  QByteArray saved_geometry_;  // where the operator left the window
  bool placed_ = false;        // placed on its screen at the first show
  bool replaying_ = false;

  void addMenus();
  // Inside the screen's available area, at most 1600 x 1000, centred.
  void fitToScreen();
  void resetLayout();
  class QDockWidget* addDock(const QString& title, const QString& name, QWidget* widget,
                             Qt::DockWidgetArea area);
};

}  // namespace ambler::widgets
