#pragma once

#include <QFutureWatcher>
#include <QThreadPool>
#include <QWidget>
#include <chrono>
#include <optional>

#include "mapping/Registration.h"
#include "mapping/ScanChain.h"
#include "mapping/TerrainMesh.h"
#include "mapping/TerrainPath.h"
#include "sensor/RangeImage.h"

class QComboBox;
class QDoubleSpinBox;
class QLabel;

namespace ambler::widgets {

class MeshTopView;

// bakambu-csa §2-4 for the operator: the ground as an irregular triangle
// mesh seen from above, each triangle coloured by its slope (red beyond the
// slope limit), and a path over it. The first click sets the start, the
// second the goal and plans; the next click starts again. The cost
// (distance, slope, high ground) and the slope limit can be changed, and
// the path is planned again. The ground is the last scan taken on demand,
// or, during a walk, every scan of the walk: each registered by ICP (in the
// background) against the one before from where dead reckoning put it,
// and merged.
class TerrainMeshPanel : public QWidget {
  Q_OBJECT

 public:
  explicit TerrainMeshPanel(QWidget* parent = nullptr);

  // The scan's returns in the world frame; meshed when the panel is shown.
  // Replaces any walk's scans.
  void setScan(const sensor::RangeImage& scan);
  // A walk's scan, placed by dead reckoning: registered against the walk's
  // previous scan and merged (queued while one is being registered).
  void addWalkScan(const sensor::RangeImage& scan);
  void clearWalkScans();
  // The walk's scans registered so far, corrected, in the world frame.
  const std::vector<mapping::Cloud>& registeredScans() const { return chain_.registered(); }
  // The ICP correction of the last registered scan (identity for the first).
  const Eigen::Isometry3d& lastCorrection() const { return chain_.last().transform; }
  bool registering() const { return watcher_.isRunning(); }
  // Clicks in world coordinates [m], as the view passes them on.
  void pick(const Eigen::Vector2d& world_xy);

  // The mesh, built now if it was waiting for the panel to be shown.
  const mapping::TerrainMesh& mesh();
  const std::optional<mapping::TerrainPath>& path() const { return path_; }
  QString readout() const;
  QWidget* meshView() const;
  // Where a world point is drawn in meshView() (for clicks in tests).
  QPointF viewPointOf(const Eigen::Vector2d& world_xy) const;
  QComboBox* costBox() const { return cost_; }
  // The triangles' outlines and the simplified path, for the 3-D view.
  std::vector<std::vector<Eigen::Vector3d>> outlines() const;
  std::vector<Eigen::Vector3d> pathPoints() const;

 signals:
  // A new mesh, or a path planned or cleared, or a scan registered.
  void overlayChanged();

 protected:
  void showEvent(QShowEvent* e) override;

 private:
  void buildMesh();
  void plan();
  void refresh();
  void useCloud(mapping::Cloud cloud);
  void dropWalkScans();
  void registerNext();
  void takeRegistration();

  MeshTopView* view_;
  QComboBox* cost_;
  QDoubleSpinBox* max_slope_;
  QLabel* readout_;
  mapping::Cloud cloud_;
  mapping::TerrainMesh mesh_;
  double mesh_ms_ = 0.0;
  std::optional<Eigen::Vector2d> start_, goal_;
  std::optional<mapping::TerrainPath> path_;
  double path_ms_ = 0.0;
  mapping::ScanChain chain_;  // the walk's scans: waiting, being registered, done
  QThreadPool background_;
  QFutureWatcher<mapping::Registration> watcher_;
  double icp_ms_ = 0.0;
  std::chrono::steady_clock::time_point icp_start_;
};

}  // namespace ambler::widgets
