#pragma once

#include <QFutureWatcher>
#include <QObject>
#include <QThreadPool>
#include <chrono>
#include <memory>
#include <optional>
#include <vector>

#include "mapping/ScanChain.h"
#include "mapping/TerrainMesh.h"
#include "mapping/TerrainPath.h"
#include "sensor/RangeImage.h"

namespace ambler::widgets {
class TerrainMeshPanel;
}

namespace ambler::gs {

// The Terrain mesh tab's work (bakambu-csa §2-4): the ground as an
// irregular triangle mesh and a path over it between two clicks. The
// ground is the last scan taken on demand or, during a walk, every scan
// of the walk, each registered by ICP against the one before (a
// mapping::ScanChain) and merged. Registration, meshing and planning run
// on worker threads (the chain at idle priority: it is bookkeeping for a
// tab); results come back by queued signals, and one that an operator's
// later change has made stale is dropped and the work redone. The panel
// draws what it is given and forwards clicks.
class MeshController : public QObject {
  Q_OBJECT

 public:
  explicit MeshController(widgets::TerrainMeshPanel& panel, QObject* parent = nullptr);
  ~MeshController() override;  // waits for the jobs under way

  // The scan's returns in the world frame; replaces any walk's scans.
  void setScan(const sensor::RangeImage& scan);
  // A walk's scan, placed by dead reckoning: registered against the walk's
  // previous scan and merged (queued while one is being registered).
  void addWalkScan(const sensor::RangeImage& scan);
  void clearWalkScans();
  // A click in world coordinates [m]: the start, then the goal (planned),
  // then a new start.
  void pick(const Eigen::Vector2d& world_xy);
  // Mesh the current ground even while the tab is hidden: the 3-D view
  // was clicked for a path. A new ground is meshed only while the tab is
  // shown, or on another such request.
  void requestMesh();

  // The walk's scans registered so far, corrected, in the world frame.
  const std::vector<mapping::Cloud>& registeredScans() const { return chain_.registered(); }
  // The ICP correction of the last registered scan (identity for the first).
  const Eigen::Isometry3d& lastCorrection() const { return chain_.last().transform; }
  bool registering() const { return chain_.busy() || chain_.waiting() > 0; }
  // The mesh of the current ground; null until built (it is built while
  // the tab is shown).
  const std::shared_ptr<const mapping::TerrainMesh>& mesh() const { return mesh_; }
  const std::optional<mapping::TerrainPath>& path() const { return path_; }
  const std::optional<Eigen::Vector2d>& start() const { return start_; }
  const std::optional<Eigen::Vector2d>& goal() const { return goal_; }
  // The triangles' outlines and the simplified path, for the 3-D view.
  std::vector<std::vector<Eigen::Vector3d>> outlines() const;
  std::vector<Eigen::Vector3d> pathPoints() const;

 signals:
  // A new mesh, a new start or goal, a path planned or cleared, or a scan
  // registered.
  void overlayChanged();
  void meshBuilt();
  void pathPlanned();

 private:
  struct MeshJob {
    std::uint64_t ground = 0;  // which ground it meshed
    std::shared_ptr<const mapping::TerrainMesh> mesh;
    double ms = 0.0;
  };
  struct PathJob {
    std::uint64_t request = 0;  // which start, goal and options it planned
    mapping::TerrainPath path;
    double ms = 0.0;
  };

  void newGround();
  void buildMesh();
  void takeMesh();
  void plan();
  void takePath();
  void registerNext();
  void takeRegistration();
  void takeJoined();
  void dropWalkScans();
  void refresh();

  widgets::TerrainMeshPanel& panel_;
  bool panel_shown_ = false;
  std::uint64_t requested_ground_ = ~std::uint64_t(0);  // requestMesh(); none yet
  // The ground: one scan's cloud, or the walk's registered scans.
  std::vector<std::shared_ptr<const mapping::Cloud>> ground_;
  std::uint64_t ground_id_ = 0;
  std::shared_ptr<const mapping::TerrainMesh> mesh_;
  double mesh_ms_ = 0.0;
  std::optional<Eigen::Vector2d> start_, goal_;
  std::optional<mapping::TerrainPath> path_;
  std::uint64_t path_request_ = 0;
  double path_ms_ = 0.0;
  mapping::ScanChain chain_;  // the walk's scans: waiting, being registered, done
  std::chrono::steady_clock::time_point icp_start_;
  double icp_ms_ = 0.0;
  QThreadPool background_;  // the chain's, at idle priority
  QFutureWatcher<mapping::Registration> icp_watcher_;
  QFutureWatcher<MeshJob> mesh_watcher_;
  QFutureWatcher<PathJob> path_watcher_;
};

}  // namespace ambler::gs
