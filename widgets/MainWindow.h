#pragma once

#include <QMainWindow>

#include "widgets/ScanDisplay.h"

class QLabel;
class QProgressBar;
class QSpinBox;
class QAction;

namespace ambler::widgets {

class RangeImageView;
class StepApprovalPanel;
class MapView;
class TerrainView;

// The operator's main window: the latest range image beside the terrain in
// 3-D. It asks for scans through scanRequested() and shows what it is given;
// where scans come from (simulator, rover, log) is not its business.
class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit MainWindow(QWidget* parent = nullptr);

  void showScan(const ScanDisplay& display);
  void showError(const QString& message);
  void setBusy(const QString& what);  // empty: idle
  quint64 seed() const;
  void setSeed(quint64 seed);

  RangeImageView* rangeView() const { return range_view_; }
  TerrainView* terrainView() const { return terrain_view_; }
  QAction* scanAction() const { return scan_action_; }
  QAction* walkAction() const { return walk_action_; }
  StepApprovalPanel* approvalPanel() const { return approval_; }
  MapView* mapView() const { return map_view_; }
  // Brings the terrain map to the front (a walk started).
  void showMapView();
  // "simulator in this process: last data 0.4 s ago"; stale shows in red.
  void setLinkStatus(const QString& text, bool stale);

 signals:
  void scanRequested(quint64 seed);
  void walkRequested();

 protected:
  void closeEvent(QCloseEvent* e) override;

 private:
  RangeImageView* range_view_;
  TerrainView* terrain_view_;
  QSpinBox* seed_box_;
  QAction* scan_action_;
  QAction* walk_action_;
  StepApprovalPanel* approval_;
  MapView* map_view_;
  class QTabWidget* views_;
  QLabel* status_;
  QLabel* link_status_;
  QProgressBar* progress_;
};

}  // namespace ambler::widgets
