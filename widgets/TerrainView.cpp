#include "widgets/TerrainView.h"

#include <vtkCamera.h>

#include <QCheckBox>
#include <QVBoxLayout>
#include <algorithm>

#include "rendering/SceneBuilders.h"
#include "rendering/VtkView.h"

namespace ambler::widgets {

TerrainView::TerrainView(QWidget* parent)
    : QWidget(parent), view_(new rendering::VtkView(this)), show_points_(new QCheckBox(this)) {
  show_points_->setText(tr("Show scan points (eq. 1, world frame)"));
  show_points_->setChecked(true);
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(view_, 1);
  layout->addWidget(show_points_);
  connect(show_points_, &QCheckBox::toggled, this, [this] { rebuild(); });
}

void TerrainView::setScene(const ScanDisplay& display) {
  display_ = display;
  rebuild();
}

void TerrainView::rebuild() {
  if (!display_) return;
  auto* renderer = view_->renderer();
  renderer->RemoveAllViewProps();

  const auto& z = display_->ground.pixels;
  float lo = INFINITY, hi = -INFINITY;
  for (float v : z)
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  auto table = rendering::makeViridisTable(lo, hi);
  renderer->AddActor(rendering::makeHeightSurface(display_->ground_grid, display_->ground, table));
  renderer->AddActor2D(rendering::makeColorBar(table, "Elevation [m]"));

  if (show_points_->isChecked()) {
    const auto& scan = display_->scan;
    std::vector<Eigen::Vector3f> points;
    points.reserve(scan.range.size());
    for (int r = 0; r < scan.rows(); ++r)
      for (int c = 0; c < scan.cols(); ++c)
        if (scan.hasReturn(r, c)) points.push_back(scan.pointInWorld(r, c).cast<float>());
    renderer->AddActor(rendering::makePointCloud(points, {0.92, 0.92, 0.92}, 1.0f));
  }

  if (!camera_placed_) {
    // Behind and above the sensor, looking along its boresight.
    const auto pose = display_->scan.sensor_to_world;
    const Eigen::Vector3d sensor = pose.translation();
    const Eigen::Vector3d ahead = pose.linear() * Eigen::Vector3d::UnitY();
    const Eigen::Vector3d forward = Eigen::Vector3d(ahead.x(), ahead.y(), 0).normalized();
    const Eigen::Vector3d eye = sensor - 8.0 * forward + Eigen::Vector3d(0, 0, 9.0);
    const Eigen::Vector3d target = sensor + 12.0 * forward - Eigen::Vector3d(0, 0, sensor.z());
    auto* camera = renderer->GetActiveCamera();
    camera->SetPosition(eye.x(), eye.y(), eye.z());
    camera->SetFocalPoint(target.x(), target.y(), target.z());
    camera->SetViewUp(0, 0, 1);
    camera_placed_ = true;
  }
  renderer->ResetCameraClippingRange();
  view_->render();
}

}  // namespace ambler::widgets
