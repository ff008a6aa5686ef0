#pragma once

#include <QWidget>
#include <memory>
#include <optional>

#include "mapping/TerrainMesh.h"
#include "mapping/TerrainPath.h"

class QComboBox;
class QDoubleSpinBox;
class QLabel;

namespace ambler::widgets {

class MeshTopView;

// bakambu-csa §2-4 for the operator: the ground as an irregular triangle
// mesh seen from above, each triangle coloured by its slope (red beyond the
// slope limit), a path over it with its start and goal, and a readout.
// It draws what it is given (gs::MeshController builds the mesh and plans
// the path) and forwards clicks, the chosen cost and slope limit, and
// whether it is shown.
class TerrainMeshPanel : public QWidget {
  Q_OBJECT

 public:
  explicit TerrainMeshPanel(QWidget* parent = nullptr);

  void showMesh(std::shared_ptr<const mapping::TerrainMesh> mesh);
  void showPath(std::optional<Eigen::Vector2d> start, std::optional<Eigen::Vector2d> goal,
                std::optional<mapping::TerrainPath> path);
  void setReadout(const QString& text);

  // The cost (distance, slope, high ground) and slope limit chosen.
  mapping::PathCost pathCost() const;
  double maxSlopeDeg() const;
  QString readout() const;
  QWidget* meshView() const;
  // Where a world point is drawn in meshView() (for clicks in tests).
  QPointF viewPointOf(const Eigen::Vector2d& world_xy) const;
  QComboBox* costBox() const { return cost_; }

 signals:
  // A click on the mesh, in world coordinates [m].
  void picked(const Eigen::Vector2d& world_xy);
  void pathOptionsChanged();
  void shownChanged(bool shown);

 protected:
  void showEvent(QShowEvent* e) override;
  void hideEvent(QHideEvent* e) override;

 private:
  MeshTopView* view_;
  QComboBox* cost_;
  QDoubleSpinBox* max_slope_;
  QLabel* readout_;
};

}  // namespace ambler::widgets
