#include "app/gs/MeshController.h"

#include <cmath>

#include "app/gs/Background.h"
#include "widgets/TerrainMeshPanel.h"

namespace ambler::gs {

namespace {

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

MeshController::MeshController(widgets::TerrainMeshPanel& panel, QObject* parent)
    : QObject(parent), panel_(panel) {
  background_.setMaxThreadCount(1);
  connect(&icp_watcher_, &QFutureWatcher<mapping::Registration>::finished, this,
          &MeshController::takeRegistration);
  connect(&mesh_watcher_, &QFutureWatcher<MeshJob>::finished, this, &MeshController::takeMesh);
  connect(&path_watcher_, &QFutureWatcher<PathJob>::finished, this, &MeshController::takePath);
  connect(&panel_, &widgets::TerrainMeshPanel::picked, this, &MeshController::pick);
  connect(&panel_, &widgets::TerrainMeshPanel::pathOptionsChanged, this, [this] {
    ++path_request_;
    plan();
  });
  // Meshing a walk's merged scans takes seconds: only while looked at.
  connect(&panel_, &widgets::TerrainMeshPanel::shownChanged, this, [this](bool shown) {
    panel_shown_ = shown;
    buildMesh();
  });
  refresh();
}

MeshController::~MeshController() {
  chain_.clear();
  icp_watcher_.waitForFinished();
  mesh_watcher_.waitForFinished();
  path_watcher_.waitForFinished();
}

void MeshController::setScan(const sensor::RangeImage& scan) {
  dropWalkScans();
  ground_ = {std::make_shared<const mapping::Cloud>(scan.pointsInWorld())};
  newGround();
}

void MeshController::clearWalkScans() {
  const bool shown = !chain_.registered().empty();
  dropWalkScans();
  if (shown) {
    ground_.clear();
    newGround();
  }
  refresh();
}

// A registration under way finishes into nothing: the chain drops it.
void MeshController::dropWalkScans() { chain_.clear(); }

void MeshController::addWalkScan(const sensor::RangeImage& scan) {
  chain_.add(scan.pointsInWorld(), scan.sensor_to_world.translation());
  registerNext();
  refresh();
}

// One scan at a time. A scan that joins the chain (the reference at once,
// the others registered) joins the ground.
void MeshController::registerNext() {
  if (icp_watcher_.isRunning()) return;
  const std::size_t before = chain_.registered().size();
  const auto job = chain_.next();
  if (chain_.registered().size() != before) takeJoined();
  if (!job) return;
  icp_start_ = std::chrono::steady_clock::now();
  icp_watcher_.setFuture(
      runInBackground(&background_, [job = *job] { return mapping::ScanChain::run(job); }));
}

void MeshController::takeRegistration() {
  icp_ms_ = msSince(icp_start_);
  const std::size_t before = chain_.registered().size();
  chain_.finish(icp_watcher_.result());  // dropped if the chain was cleared meanwhile
  if (chain_.registered().size() != before) takeJoined();
  registerNext();
}

// The scan that joined the chain joins the ground; the walk's first
// replaces the scan shown before.
void MeshController::takeJoined() {
  if (chain_.registered().size() == 1) ground_.clear();
  ground_.push_back(std::make_shared<const mapping::Cloud>(chain_.registered().back()));
  newGround();
}

// The ground changed: the mesh and any path over it go, and a new mesh is
// built if the tab is looked at.
void MeshController::newGround() {
  ++ground_id_;
  const bool had_overlay = mesh_ != nullptr || path_.has_value();
  mesh_.reset();
  start_.reset(), goal_.reset(), path_.reset();
  ++path_request_;
  buildMesh();
  if (had_overlay || !chain_.registered().empty()) emit overlayChanged();
  refresh();
}

void MeshController::requestMesh() {
  requested_ground_ = ground_id_;
  buildMesh();
}

void MeshController::buildMesh() {
  const bool wanted = panel_shown_ || requested_ground_ == ground_id_;
  if (!wanted || mesh_ || mesh_watcher_.isRunning()) return;
  std::size_t points = 0;
  for (const auto& part : ground_) points += part->size();
  if (points < 3) return;
  mesh_watcher_.setFuture(runInBackground([ground = ground_, id = ground_id_, points] {
    const auto start = std::chrono::steady_clock::now();
    mapping::Cloud cloud;
    cloud.reserve(points);
    for (const auto& part : ground) cloud.insert(cloud.end(), part->begin(), part->end());
    MeshJob job;
    job.ground = id;
    job.mesh = std::make_shared<const mapping::TerrainMesh>(mapping::triangulate(cloud));
    job.ms = msSince(start);
    return job;
  }));
  refresh();
}

void MeshController::takeMesh() {
  auto job = mesh_watcher_.result();
  if (job.ground != ground_id_) return buildMesh();  // the ground changed meanwhile
  mesh_ = std::move(job.mesh);
  mesh_ms_ = job.ms;
  panel_.showMesh(mesh_);
  emit meshBuilt();
  emit overlayChanged();
  refresh();
}

void MeshController::pick(const Eigen::Vector2d& xy) {
  if (!mesh_ || mesh_->size() == 0) return;
  if (!start_ || goal_) {
    start_ = xy;
    goal_.reset();
    path_.reset();
    ++path_request_;
    refresh();
    emit overlayChanged();
    return;
  }
  goal_ = xy;
  ++path_request_;
  plan();
  emit overlayChanged();
}

void MeshController::plan() {
  if (!start_ || !goal_ || !mesh_ || path_watcher_.isRunning()) return refresh();
  mapping::PathOptions options;
  options.cost = panel_.pathCost();
  options.max_slope_deg = panel_.maxSlopeDeg();
  path_watcher_.setFuture(runInBackground(
      [mesh = mesh_, from = *start_, to = *goal_, options, request = path_request_] {
        const auto start = std::chrono::steady_clock::now();
        PathJob job{request, mapping::planPath(*mesh, from, to, options), 0.0};
        job.ms = msSince(start);
        return job;
      }));
  refresh();
}

void MeshController::takePath() {
  auto job = path_watcher_.result();
  if (job.request != path_request_) return plan();  // asked again meanwhile
  path_ = std::move(job.path);
  path_ms_ = job.ms;
  emit pathPlanned();
  emit overlayChanged();
  refresh();
}

std::vector<std::vector<Eigen::Vector3d>> MeshController::outlines() const {
  std::vector<std::vector<Eigen::Vector3d>> out;
  if (!mesh_) return out;
  for (int t = 0; t < int(mesh_->size()); ++t)
    out.push_back(
        {mesh_->corner(t, 0), mesh_->corner(t, 1), mesh_->corner(t, 2), mesh_->corner(t, 0)});
  return out;
}

std::vector<Eigen::Vector3d> MeshController::pathPoints() const {
  return path_ && path_->found ? path_->simplified : std::vector<Eigen::Vector3d>{};
}

// The panel's drawing and its readout: registration, mesh, path, and what
// the next click does.
void MeshController::refresh() {
  panel_.showMesh(mesh_);
  panel_.showPath(start_, goal_, path_);
  QString text;
  const auto& registered = chain_.registered();
  if (registered.size() > 1) {
    const auto& last = chain_.last();
    const Eigen::Vector3d t = last.transform.translation();
    const QString verdict = QString::fromUtf8(mapping::verdictName(last.quality.verdict));
    const QString how =
        last.quality.reason.empty()
            ? verdict
            : tr("%1: %2").arg(verdict, QString::fromStdString(last.quality.reason));
    text =
        mapping::ScanChain::applies(last)
            ? tr("%1 walk scans registered and merged; the last moved %2 m and %3° "
                 "(%4; rms %5 cm, overlap %6 %, %7 s). ")
                  .arg(registered.size())
                  .arg(t.norm(), 0, 'f', 3)
                  .arg(Eigen::AngleAxisd(last.transform.linear()).angle() * 180 / M_PI, 0, 'f', 2)
                  .arg(how)
                  .arg(100 * last.rms_m, 0, 'f', 1)
                  .arg(100 * last.quality.overlap, 0, 'f', 0)
                  .arg(icp_ms_ / 1000, 0, 'f', 1)
            : tr("%1 walk scans merged; the last kept where dead reckoning put it, its "
                 "registration not applied (%2). ")
                  .arg(registered.size())
                  .arg(how);
  }
  if (registering())
    text += tr("Registering %1 scan(s)… ").arg(chain_.waiting() + (chain_.busy() ? 1 : 0));
  if (mesh_watcher_.isRunning() && !mesh_) text += tr("Meshing… ");
  if (mesh_ && mesh_->size() > 0)
    text += tr("Mesh%1: %2 triangles, %3 vertices (%4 ms). ")
                .arg(registered.size() > 1 ? tr(" of the merged scans") : tr(" of the last scan"))
                .arg(mesh_->size())
                .arg(mesh_->vertices.size())
                .arg(mesh_ms_, 0, 'f', 0);
  if (!start_)
    text += tr("Click the start.");
  else if (!goal_)
    text += tr("Start at x %1, y %2 m; click the goal.")
                .arg(start_->x(), 0, 'f', 1)
                .arg(start_->y(), 0, 'f', 1);
  else if (path_watcher_.isRunning())
    text += tr("Planning…");
  else if (path_ && path_->found)
    text += tr("Path: %1 m, %2 waypoints (%3 before simplifying), cost %4 (raw %5), %6 ms.")
                .arg(path_->length_m, 0, 'f', 2)
                .arg(path_->simplified.size())
                .arg(path_->raw.size())
                .arg(path_->simplified_cost, 0, 'f', 1)
                .arg(path_->raw_cost, 0, 'f', 1)
                .arg(path_ms_, 0, 'f', 1);
  else if (path_)
    text += tr("No path: %1.").arg(QString::fromStdString(path_->reason));
  panel_.setReadout(text);
}

}  // namespace ambler::gs
