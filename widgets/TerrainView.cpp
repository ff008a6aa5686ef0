#include "widgets/TerrainView.h"

#include <vtkCamera.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>

#include <QCheckBox>
#include <QHBoxLayout>
#include <QTimer>
#include <QToolTip>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <utility>

#include "rendering/SceneBuilders.h"
#include "rendering/VtkView.h"

#include <array>

namespace ambler::widgets {

TerrainView::TerrainView(QWidget* parent)
    : QWidget(parent),
      view_(new rendering::VtkView(this)),
      show_points_(new QCheckBox(this)),
      show_mesh_(new QCheckBox(this)) {
  show_points_->setText(tr("Scan points"));
  show_points_->setToolTip(
      tr("Scan points in the world frame; a walk's registered scans in colour"));
  show_points_->setChecked(true);
  show_mesh_->setText(tr("Terrain mesh and path"));
  show_mesh_->setToolTip(
      tr("The Terrain mesh tab's triangles and path; while shown, a click on the ground sets "
         "the path's start, the next its goal"));
  show_mesh_->setChecked(true);
  auto* options = new QHBoxLayout;
  options->addWidget(show_points_);
  options->addWidget(show_mesh_);
  options->addStretch();
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(view_, 1);
  layout->addLayout(options);
  connect(show_points_, &QCheckBox::toggled, this, [this] {
    scheduleRebuild({kGround, kOverlay});
  });
  connect(show_mesh_, &QCheckBox::toggled, this, [this] { scheduleRebuild({kOverlay}); });
  connect(view_, &rendering::VtkView::clicked, this, &TerrainView::pickGround);
}

void TerrainView::pickGround(QPointF position) {
  if (!show_mesh_->isChecked()) return;
  // The mesh is built while its tab is looked at, or when asked for here.
  if (mesh_outlines_.empty()) {
    QToolTip::showText(view_->mapToGlobal(position.toPoint()),
                       tr("No terrain mesh yet: building it (a few seconds); click the path's "
                          "start again once its outlines are drawn"),
                       view_);
    emit meshWanted();
    return;
  }
  view_->pick(position, [this](std::optional<Eigen::Vector3d> at) {
    if (at) emit groundPicked(at->head<2>());
  });
}

void TerrainView::setPathEnds(const std::optional<Eigen::Vector2d>& start,
                              const std::optional<Eigen::Vector2d>& goal) {
  path_start_ = start;
  path_goal_ = goal;
  scheduleRebuild({kOverlay});
}

std::pair<const GridSpec&, const io::FloatImage&> TerrainView::drawnGround() const {
  if (map_ground_) return {map_ground_->first, map_ground_->second};
  return {display_->ground_grid, display_->ground};
}

std::optional<double> TerrainView::groundHeightAt(const Eigen::Vector2d& xy) const {
  if (!map_ground_ && !display_) return std::nullopt;
  const auto [grid, ground] = drawnGround();
  const auto cell = grid.cellAt(xy.x(), xy.y());
  if (!cell || !std::isfinite(ground(cell->row, cell->col))) return std::nullopt;
  return double(ground(cell->row, cell->col));
}

void TerrainView::setMeshOverlay(std::vector<std::vector<Eigen::Vector3d>> outlines,
                                 std::vector<Eigen::Vector3d> path) {
  mesh_outlines_ = std::move(outlines);
  mesh_path_ = std::move(path);
  scheduleRebuild({kOverlay});
}

void TerrainView::setRegisteredScans(const std::vector<std::vector<Eigen::Vector3d>>& scans) {
  registered_.clear();
  std::size_t total = 0;
  for (const auto& scan : scans) total += scan.size();
  // All of them together within half the budget of a surface: they show
  // whether the scans agree, not the ground's detail.
  const std::size_t budget = kDetailLimit / 2;
  const std::size_t k = std::max<std::size_t>(1, (total + budget - 1) / budget);
  for (const auto& scan : scans) {
    std::vector<Eigen::Vector3f> few;
    for (std::size_t i = 0; i < scan.size(); i += k) few.push_back(scan[i].cast<float>());
    registered_.push_back(std::move(few));
  }
  scheduleRebuild({kOverlay});
}

// One colour per scan, in the order they came, so that where two overlap
// the operator sees whether they agree; single pixels, so that the
// surface's colours, which the colour bar explains, show between them.
void TerrainView::addRegisteredScans() {
  if (!show_points_->isChecked()) return;
  static const std::array<std::array<double, 3>, 6> kColours{{{1.0, 0.55, 0.1},
                                                              {0.2, 0.8, 1.0},
                                                              {0.95, 0.3, 0.9},
                                                              {0.5, 1.0, 0.3},
                                                              {1.0, 0.9, 0.2},
                                                              {0.6, 0.6, 1.0}}};
  for (std::size_t i = 0; i < registered_.size(); ++i) {
    const auto& c = kColours[i % kColours.size()];
    addTo(kOverlay, rendering::makePointCloud(registered_[i], {c[0], c[1], c[2]}, 1.0f));
  }
}

// Lifted a few centimetres so the ground surface does not hide them.
void TerrainView::addMeshOverlay() {
  if (!show_mesh_->isChecked()) return;
  const Eigen::Vector3d lift(0, 0, 0.03);
  auto lifted = [&](std::vector<Eigen::Vector3d> line) {
    for (auto& p : line) p += lift;
    return line;
  };
  if (!mesh_outlines_.empty()) {
    std::vector<std::vector<Eigen::Vector3d>> outlines;
    for (const auto& o : mesh_outlines_) outlines.push_back(lifted(o));
    addTo(kOverlay, rendering::makePolylines(outlines, {0.8, 0.8, 0.8}, 1.0f));
  }
  if (mesh_path_.size() >= 2)
    addTo(kOverlay, rendering::makePolylines({lifted(mesh_path_)}, {0.0, 0.9, 1.0}, 5.0f));
  // The start green, the goal magenta, each on the ground under it.
  for (const auto& [end, rgb] : {std::pair{path_start_, Eigen::Vector3d(0.2, 0.9, 0.3)},
                                 std::pair{path_goal_, Eigen::Vector3d(0.95, 0.3, 0.9)}})
    if (const auto z = end ? groundHeightAt(*end) : std::nullopt)
      addTo(kOverlay, rendering::makeSphere({end->x(), end->y(), *z + 0.15}, 0.3, rgb));
}

void TerrainView::setScene(const ScanDisplay& display) {
  display_ = display;
  scan_over_map_ = true;
  stale_[kGround] = true;
  rebuild();  // at once: the first scan's frame is what a launch waits for
}

void TerrainView::clear() {
  display_.reset();
  map_ground_.reset();
  mesh_outlines_.clear();
  mesh_path_.clear();
  path_start_.reset();
  path_goal_.reset();
  registered_.clear();
  scheduleRebuild({kGround, kOverlay});
}

void TerrainView::setMap(const terrain::ElevationMap& map) {
  if (map.knownCount() == 0) return;
  // The whole traverse so far: the extent of its known cells, thinned to
  // at most kDetailLimit cells (about 0.2 m over a 50 m walk), so that the
  // view keeps up on software OpenGL, still or orbiting.
  const GridSpec& g = map.grid();
  int r0 = g.rows, r1 = -1, c0 = g.cols, c1 = -1;
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c)
      if (map.hasHeight(r, c))
        r0 = std::min(r0, r), r1 = std::max(r1, r), c0 = std::min(c0, c), c1 = std::max(c1, c);
  r0 = std::max(0, r0 - 1), c0 = std::max(0, c0 - 1);
  r1 = std::min(g.rows, r1 + 2), c1 = std::min(g.cols, c1 + 2);
  if (c1 - c0 < 2 || r1 - r0 < 2) return;
  GridSpec sub = g;
  sub.origin_x = g.origin_x + c0 * g.resolution, sub.origin_y = g.origin_y + r0 * g.resolution;
  sub.rows = r1 - r0, sub.cols = c1 - c0;
  io::FloatImage z(sub.rows, sub.cols);
  for (int r = 0; r < sub.rows; ++r)
    for (int c = 0; c < sub.cols; ++c) z(r, c) = map.elevation(r0 + r, c0 + c);
  map_ground_ = rendering::thinned(sub, z, kDetailLimit);
  scan_over_map_ = false;
  scheduleRebuild({kGround});
}

void TerrainView::setRover(const std::optional<RoverDisplay>& rover, const gait::RoverModel& model,
                           const std::optional<executive::StepProposal>& proposal) {
  rover_ = rover;
  model_ = model;
  proposal_ = proposal;
  scheduleRebuild({kRover});
}

// The body as its keep-out box at the link plane, each leg as its shaft,
// horizontal link and vertical link down to the foot; supporting feet
// white, lifted ones orange; the conservative support polygon in cyan just
// above the feet.
void TerrainView::addRover() {
  if (!rover_) return;
  const auto& stance = rover_->stance;
  const auto& body = stance.body;
  const auto& h = model_.body_keepout_half;
  std::vector<Eigen::Vector3d> outline;
  for (const auto& corner : {Eigen::Vector2d(-h.x(), -h.y()), Eigen::Vector2d(h.x(), -h.y()),
                             Eigen::Vector2d(h.x(), h.y()), Eigen::Vector2d(-h.x(), h.y()),
                             Eigen::Vector2d(-h.x(), -h.y())})
    outline.push_back(body.toWorld(Eigen::Vector3d(corner.x(), corner.y(), 0.0)));
  std::vector<std::vector<Eigen::Vector3d>> legs;
  for (int leg = 0; leg < gait::kLegCount; ++leg) {
    const Eigen::Vector3d foot = stance.feet[std::size_t(leg)];
    const Eigen::Vector3d foot_b = body.toBody(foot);
    const Eigen::Vector2d shaft = model_.shaftOf(leg);
    legs.push_back({body.toWorld(Eigen::Vector3d(shaft.x(), shaft.y(), 0.6)),
                    body.toWorld(Eigen::Vector3d(shaft.x(), shaft.y(), 0.0)),
                    body.toWorld(Eigen::Vector3d(foot_b.x(), foot_b.y(), 0.0)), foot});
    const bool supporting = stance.supporting[std::size_t(leg)];
    addTo(kRover, rendering::makeSphere(foot, 0.15,
                                        supporting ? Eigen::Vector3d(0.95, 0.95, 0.95)
                                                   : Eigen::Vector3d(1.0, 0.6, 0.1)));
  }
  addTo(kRover, rendering::makePolylines({outline}, {0.3, 0.9, 1.0}, 3.0f));
  addTo(kRover, rendering::makePolylines(legs, {1.0, 0.85, 0.3}, 4.0f));
  int supporting = 0;
  double z_sum = 0.0;
  for (int leg = 0; leg < gait::kLegCount; ++leg)
    if (stance.supporting[std::size_t(leg)]) {
      ++supporting;
      z_sum += stance.feet[std::size_t(leg)].z();
    }
  const double z = supporting == 0 ? 0.0 : z_sum / double(supporting);
  std::vector<Eigen::Vector3d> csp;
  for (const auto& v : rover_->support_polygon) csp.push_back({v.x(), v.y(), z + 0.05});
  if (csp.size() >= 3) {
    csp.push_back(csp.front());
    addTo(kRover, rendering::makePolylines({csp}, {0.0, 0.9, 1.0}, 3.0f));
  }
}

// The recovering leg's foot trajectory and foothold (red) and the body's
// path at the link plane (white).
void TerrainView::addProposal() {
  if (!proposal_) return;
  const auto& plan = proposal_->plan;
  if (plan.leg >= 0) {
    addTo(kRover, rendering::makeSphere(plan.foothold, 0.2, {1.0, 0.2, 0.2}));
    if (!proposal_->foot_path.empty())
      addTo(kRover, rendering::makePolylines({proposal_->foot_path}, {1.0, 0.35, 0.35}, 3.0f));
  }
  std::vector<Eigen::Vector3d> body;
  for (const auto& pose : plan.body_path) body.push_back({pose.xy.x(), pose.xy.y(), pose.link_z});
  addTo(kRover, rendering::makePolylines({body}, {1.0, 1.0, 1.0}, 3.0f));
}

// Changes that come together (the map, the rover, the proposal after a
// step) cost one rebuild of the layers they touch, once the event loop is
// free.
void TerrainView::scheduleRebuild(std::initializer_list<Layer> layers) {
  for (Layer layer : layers) stale_[layer] = true;
  if (std::exchange(rebuild_pending_, true)) return;
  QTimer::singleShot(0, this, [this] {
    if (rebuild_pending_) rebuild();
  });
}

void TerrainView::addTo(Layer layer, vtkSmartPointer<vtkProp> prop, bool pickable) {
  prop->SetPickable(pickable);
  props_[layer].push_back(prop.Get());
  view_->add(std::move(prop));
}

void TerrainView::addToWithStandIn(Layer layer, vtkSmartPointer<vtkProp> detailed,
                                   vtkSmartPointer<vtkProp> stand_in, bool pickable) {
  detailed->SetPickable(pickable);
  stand_in->SetPickable(pickable);
  props_[layer].push_back(detailed.Get());
  view_->addWithStandIn(std::move(detailed), std::move(stand_in));
}

void TerrainView::rebuild() {
  rebuild_pending_ = false;
  const bool empty = !display_ && !map_ground_;
  for (int layer = 0; layer < kLayerCount; ++layer) {
    if (!empty && !std::exchange(stale_[layer], false)) continue;
    for (vtkProp* prop : props_[layer]) view_->remove(prop);
    props_[layer].clear();
    // Nothing to draw: not the old scene, and every layer drawn again once
    // there is a scene.
    if (empty) {
      stale_[layer] = true;
      continue;
    }
    switch (Layer(layer)) {
      case kGround:
        addGround();
        addScanPoints();
        break;
      case kRover:
        addRover();
        addProposal();
        break;
      case kOverlay:
        addMeshOverlay();
        addRegisteredScans();
        break;
      case kLayerCount:
        break;
    }
  }
  if (empty) return view_->render();
  if (!camera_placed_) {
    if (display_) {
      const auto pose = display_->scan.sensor_to_world;
      const Eigen::Vector3d sensor = pose.translation();
      // The ground under the sensor, wherever the terrain's datum puts it
      // (a Mars DTM's heights are thousands of metres below zero).
      const auto cell = display_->ground_grid.cellAt(sensor.x(), sensor.y());
      const float ground = cell ? display_->ground(cell->row, cell->col) : NAN;
      placeCamera(sensor, pose.linear() * Eigen::Vector3d::UnitY(),
                  std::isfinite(ground) ? double(ground) : sensor.z() - 5.0);
    } else if (rover_) {
      const auto& stance = rover_->stance;
      double ground = 0.0;
      for (const auto& f : stance.feet) ground += f.z() / double(stance.feet.size());
      placeCamera(stance.body.toWorld(Eigen::Vector3d(0, 0, 0)),
                  stance.body.toWorld(Eigen::Vector3d(0, 1, 0)) -
                      stance.body.toWorld(Eigen::Vector3d(0, 0, 0)),
                  ground);
    }
  }
  view_->edit([](vtkRenderer& renderer) { renderer.ResetCameraClippingRange(); });
  view_->render();
}

// The walk's map or the simulated ground, coloured by elevation, with its
// colour bar.
void TerrainView::addGround() {
  const auto [grid, ground] = drawnGround();
  float lo = INFINITY, hi = -INFINITY;
  for (float v : ground.pixels)
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (lo > hi) return;  // no known height: no surface, and no colour bar of NaN
  auto table = rendering::makeViridisTable(lo, hi);
  if (grid.cellCount() > kDetailLimit) {
    const auto [thin_grid, thin] = rendering::thinned(grid, ground, kDetailLimit);
    addToWithStandIn(kGround, rendering::makeHeightSurface(grid, ground, table),
                     rendering::makeHeightSurface(thin_grid, thin, table), true);
  } else {
    addTo(kGround, rendering::makeHeightSurface(grid, ground, table), true);
  }
  addTo(kGround,
        rendering::makeColorBar(table, map_ground_ ? "Map\nelevation [m]" : "Elevation [m]",
                                devicePixelRatioF()));
}

void TerrainView::addScanPoints() {
  // Over a walk's map, only the points of a scan that came after it.
  if (!display_ || (map_ground_ && !scan_over_map_) || !show_points_->isChecked()) return;
  const auto& scan = display_->scan;
  std::vector<Eigen::Vector3f> points;
  points.reserve(scan.range.size());
  for (int r = 0; r < scan.rows(); ++r)
    for (int c = 0; c < scan.cols(); ++c)
      if (scan.hasReturn(r, c)) points.push_back(scan.pointInWorld(r, c).cast<float>());
  auto cloud = rendering::makePointCloud(points, {0.92, 0.92, 0.92}, 1.0f);
  cloud->GetProperty()->SetOpacity(0.35);  // the surface shows through
  if (points.size() <= std::size_t(kDetailLimit)) return addTo(kGround, cloud);
  const std::size_t k = (points.size() + kDetailLimit - 1) / kDetailLimit;
  std::vector<Eigen::Vector3f> few;
  for (std::size_t i = 0; i < points.size(); i += k) few.push_back(points[i]);
  auto stand_in = rendering::makePointCloud(few, {0.92, 0.92, 0.92}, 1.0f);
  stand_in->GetProperty()->SetOpacity(0.35);
  addToWithStandIn(kGround, cloud, stand_in);
}

// Behind and above the sensor (or body), looking along `ahead` at the
// ground (height `ground_z`) 10 m ahead, far enough back that the rover's
// feet and the terrain 30 m ahead are both in view.
void TerrainView::placeCamera(const Eigen::Vector3d& sensor, const Eigen::Vector3d& ahead,
                              double ground_z) {
  const Eigen::Vector3d forward = Eigen::Vector3d(ahead.x(), ahead.y(), 0).normalized();
  const Eigen::Vector3d eye = sensor - 18.0 * forward + Eigen::Vector3d(0, 0, 7.0);
  Eigen::Vector3d target = sensor + 10.0 * forward;
  target.z() = ground_z;
  view_->edit([eye, target](vtkRenderer& renderer) {
    auto* camera = renderer.GetActiveCamera();
    camera->SetPosition(eye.x(), eye.y(), eye.z());
    camera->SetFocalPoint(target.x(), target.y(), target.z());
    camera->SetViewUp(0, 0, 1);
    // The colour bar takes the right fifth of the view (from
    // rendering::kColorBarLeft). A wide scene seen
    // from behind: its share of the width is the same in any view when the
    // view angle is horizontal, and with its middle moved left by a
    // twentieth of the width it ends short of the bar.
    camera->UseHorizontalViewAngleOn();
    camera->SetViewAngle(40.0);
    camera->SetWindowCenter(0.1, 0.0);
  });
  camera_placed_ = true;
}

}  // namespace ambler::widgets
