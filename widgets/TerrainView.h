#pragma once

#include <vtkSmartPointer.h>

#include <QWidget>
#include <array>
#include <initializer_list>
#include <optional>
#include <utility>
#include <vector>

#include "executive/ApprovalGate.h"
#include "terrain/ElevationMap.h"
#include "widgets/RoverDisplay.h"
#include "widgets/ScanDisplay.h"

class QCheckBox;
class vtkProp;

namespace ambler::rendering {
class VtkView;
}

namespace ambler::widgets {

// The 3-D view: the ground as a shaded surface coloured by elevation (with
// a colour bar in metres): the simulated ground of the last scan, or the
// walk's terrain map once there is one; the scan's points in the world
// frame; the rover with its legs as it reports them, its conservative
// support polygon, and the proposed step: the leg's trajectory, foothold
// and the body's path. The camera starts behind and above the rover and is
// kept across updates. Surfaces and clouds above kDetailLimit elements
// are drawn thinned while the camera moves.
class TerrainView : public QWidget {
  Q_OBJECT

 public:
  explicit TerrainView(QWidget* parent = nullptr);

  // A scan and the ground under it (a walk's map, when there is one, stays
  // the ground; the scan's points are drawn over it until the next map).
  void setScene(const ScanDisplay& display);
  // Drops the scan, the map, the mesh overlay and registered scans: a
  // replay shows only the log's state, nothing before its first scan.
  void clear();
  // The whole traverse map replaces the simulated ground (at most
  // kDetailLimit cells: thinned on a long walk).
  void setMap(const terrain::ElevationMap& map);
  // The rover (body, legs, support polygon: the stance a pending step
  // starts from, else the reported one) and the proposal's foot path,
  // foothold and body path.
  void setRover(const std::optional<RoverDisplay>& rover, const gait::RoverModel& model,
                const std::optional<executive::StepProposal>& proposal);

  // The terrain mesh's triangle outlines (grey) and a path over it (cyan),
  // drawn when "Show terrain mesh" is ticked; empty ones clear them.
  void setMeshOverlay(std::vector<std::vector<Eigen::Vector3d>> outlines,
                      std::vector<Eigen::Vector3d> path);
  // A walk's scans after registration, each in its own colour, drawn with
  // the scan points.
  void setRegisteredScans(const std::vector<std::vector<Eigen::Vector3d>>& scans);

  // The path's start and goal (the Terrain mesh tab's), marked on the
  // ground with the mesh.
  void setPathEnds(const std::optional<Eigen::Vector2d>& start,
                   const std::optional<Eigen::Vector2d>& goal);

  static constexpr int kDetailLimit =
      20000;  // cells or points of a map, a stand-in, the registered scans
  rendering::VtkView* view() const { return view_; }
  QSize sizeHint() const override { return {640, 480}; }

 signals:
  // A click on the ground while the terrain mesh and path are shown: a
  // start or goal for the path, in the world frame [m].
  void groundPicked(const Eigen::Vector2d& world_xy);
  // A click for a path before there is a mesh to plan it on.
  void meshWanted();

 private:
  // The scene in layers, each rebuilt only when what it draws changed: a
  // step's new stance does not rebuild the ground's surface.
  enum Layer { kGround, kRover, kOverlay, kLayerCount };
  void scheduleRebuild(std::initializer_list<Layer> layers);
  void rebuild();
  // Only the ground is pickable: a click meets it through the rover and
  // the points drawn over it.
  void addTo(Layer layer, vtkSmartPointer<vtkProp> prop, bool pickable = false);
  void addToWithStandIn(Layer layer, vtkSmartPointer<vtkProp> detailed,
                        vtkSmartPointer<vtkProp> stand_in, bool pickable = false);
  void pickGround(QPointF position);
  // The ground drawn: the walk's map, else the scan's simulated ground.
  std::pair<const GridSpec&, const io::FloatImage&> drawnGround() const;
  std::optional<double> groundHeightAt(const Eigen::Vector2d& xy) const;
  void addGround();
  void addScanPoints();
  void addRover();
  void addProposal();
  void addMeshOverlay();
  void addRegisteredScans();
  void placeCamera(const Eigen::Vector3d& sensor, const Eigen::Vector3d& ahead, double ground_z);

  rendering::VtkView* view_;
  QCheckBox* show_points_;
  QCheckBox* show_mesh_;
  std::vector<std::vector<Eigen::Vector3d>> mesh_outlines_;
  std::vector<Eigen::Vector3d> mesh_path_;
  std::optional<Eigen::Vector2d> path_start_, path_goal_;
  std::vector<std::vector<Eigen::Vector3f>> registered_;  // thinned for drawing
  std::optional<ScanDisplay> display_;
  std::optional<std::pair<GridSpec, io::FloatImage>> map_ground_;
  std::optional<RoverDisplay> rover_;
  gait::RoverModel model_;
  std::optional<executive::StepProposal> proposal_;
  bool scan_over_map_ = false;  // the scan came after the map: its points are drawn
  bool camera_placed_ = false;
  bool rebuild_pending_ = false;
  // Owned by the view's scene; kept here only to name them for removal.
  std::array<std::vector<vtkProp*>, kLayerCount> props_;
  std::array<bool, kLayerCount> stale_{};
};

}  // namespace ambler::widgets
