#include "app/gs/GroundStation.h"

#include <QApplication>
#include <QCheckBox>
#include <QDateTime>
#include <QDir>
#include <QStatusBar>
#include <cmath>
#include <utility>

#include "app/gs/Background.h"
#include "app/gs/DdsConnection.h"
#include "gait/Support.h"
#include "link/Signing.h"
#include "missionlog/ReplayLinks.h"
#include "widgets/CommandLogView.h"
#include "widgets/MapView.h"
#include "widgets/RangeImageView.h"
#include "widgets/SamplingPanel.h"
#include "widgets/StepApprovalPanel.h"
#include "widgets/TelemetryPanel.h"
#include "widgets/TerrainView.h"
#include "widgets/TimelineBar.h"

namespace ambler::gs {

namespace {

gait::Heading headingFor(const widgets::WalkCommand& c) {
  using Path = widgets::WalkCommand::Path;
  switch (c.path) {
    case Path::kArcLeft:
      return {c.radius_m};
    case Path::kArcRight:
      return {-c.radius_m};
    case Path::kTurnLeft:
      return {0.0, true};
    case Path::kTurnRight:
      return {0.0, false};
    case Path::kStraight:
      break;
  }
  return {};
}

// The toolbar's command for a walk started elsewhere (--walk, the soak),
// keeping the bar's radius where the walk has none.
widgets::WalkCommand commandFor(int steps, const gait::Heading& heading, double shown_radius_m) {
  using Path = widgets::WalkCommand::Path;
  if (heading.isPointTurn())
    return {steps, heading.point_turn_left ? Path::kTurnLeft : Path::kTurnRight, shown_radius_m};
  if (!std::isfinite(heading.radius_m)) return {steps, Path::kStraight, shown_radius_m};
  return {steps, heading.radius_m > 0 ? Path::kArcLeft : Path::kArcRight,
          std::abs(heading.radius_m)};
}

bool sameStance(const std::optional<gait::Stance>& a, const std::optional<gait::Stance>& b) {
  if (!a || !b) return a.has_value() == b.has_value();
  return a->body.xy == b->body.xy && a->body.heading_rad == b->body.heading_rad &&
         a->body.link_z == b->body.link_z && a->feet == b->feet && a->supporting == b->supporting;
}

// The stance as the views draw it, with the support polygon of its
// supporting feet.
std::optional<widgets::RoverDisplay> drawn(const std::optional<gait::Stance>& stance) {
  if (!stance) return std::nullopt;
  return widgets::RoverDisplay{*stance, gait::conservativeSupportPolygon(stance->supportingFeet())};
}

}  // namespace

GroundStation::GroundStation(StationOptions options, QObject* parent)
    : QObject(parent),
      options_(std::move(options)),
      simulator_(options_.scanner, options_.simulated_ground),
      choice_(launchedSimulator()) {
  wireWindow();
  connect(window_.terrainView(), &widgets::TerrainView::groundPicked, &mesh_,
          &MeshController::pick);
  connect(window_.terrainView(), &widgets::TerrainView::meshWanted, &mesh_,
          &MeshController::requestMesh);
  connect(&mesh_, &MeshController::overlayChanged, this, [this] {
    window_.terrainView()->setMeshOverlay(mesh_.outlines(), mesh_.pathPoints());
    window_.terrainView()->setPathEnds(mesh_.start(), mesh_.goal());
    window_.terrainView()->setRegisteredScans(mesh_.registeredScans());
  });
  connect(&open_watcher_, &QFutureWatcher<std::shared_ptr<replay::MissionTimeline>>::finished, this,
          &GroundStation::finishOpening);
  connect(&progress_timer_, &QTimer::timeout, this, [this] {
    if (!progress_dialog_ || !opening_) return;
    progress_dialog_->setMaximum(std::max(1, opening_->total.load()));
    progress_dialog_->setValue(opening_->done.load());
  });
  connect(&refresh_timer_, &QTimer::timeout, this, &GroundStation::refreshTelemetry);
  refresh_timer_.start(500);
  window_.setSeed(options_.seed);
  report(connectTo(choice_));
}

widgets::ConnectChoice GroundStation::launchedSimulator() const {
  widgets::ConnectChoice c;
  c.seed = options_.seed;
  c.family = options_.simulated_ground.family;
  c.on_terrain_model = options_.simulated_ground.dtm.has_value();
  return c;
}

rover::SimulatedGround GroundStation::groundOf(const widgets::ConnectChoice& choice) const {
  rover::SimulatedGround ground = options_.simulated_ground;
  ground.family = choice.family;
  return ground;
}

bool GroundStation::report(const Refusal& refusal) {
  if (refusal.refused()) window_.showError(QString::fromStdString(refusal.why()));
  return refusal.refused();
}

GroundStation::~GroundStation() {
  if (opening_) opening_->cancel = true;
  open_watcher_.waitForFinished();
}

void GroundStation::wireWindow() {
  connect(&window_, &widgets::MainWindow::scanRequested, &simulator_, [this](quint64 s) {
    window_.setBusy(
        tr("Scanning the simulated %1…").arg(QString::fromStdString(groundOf(choice_).name(s))));
    simulator_.requestScan(s);
  });
  connect(&simulator_, &SimulatorSource::scanReady, &window_,
          [this](const widgets::ScanDisplay& d) {
            window_.setBusy({});
            window_.showScan(d);
            mesh_.setScan(d.scan);
          });
  connect(&simulator_, &SimulatorSource::scanFailed, &window_, [this](const QString& message) {
    window_.setBusy({});
    window_.showError(message);
  });
  connect(&window_, &widgets::MainWindow::walkRequested, this,
          [this](const widgets::WalkCommand& c) { startWalk(c.steps, headingFor(c)); });
  connect(&window_, &widgets::MainWindow::holdRequested, this, [this] {
    if (session_ && !timeline_) session_->hold();
  });
  connect(&window_, &widgets::MainWindow::authorityRequested, this, [this] {
    if (session_ && !timeline_) session_->requestAuthority();
  });
  connect(&window_, &widgets::MainWindow::handOverRequested, this, [this] {
    if (session_ && !timeline_) session_->handOver();
  });
  connect(&window_, &widgets::MainWindow::openLogRequested, this, &GroundStation::openLog);
  connect(&window_, &widgets::MainWindow::connectRequested, this, [this] {
    widgets::ConnectDialog dialog(choice_, &window_);
    if (dialog.exec() == QDialog::Accepted) report(connectTo(dialog.choice()));
  });
  connect(window_.timeline(), &widgets::TimelineBar::timeChanged, this,
          &GroundStation::showReplayAt);

  auto* sampling = window_.samplingPanel();
  connect(&sampling_, &SamplingController::graspApproved, this,
          [this, sampling](const sampling::GraspPlan& plan, const QString& fit) {
            if (timeline_) return sampling->setGraspAnswer(tr("a replay cannot command"), false);
            if (!session_ && report(openSession())) return;
            sampling->setGraspAnswer(tr("Sending the grasp…"), false);
            session_->sendGrasp(plan, fit.toStdString());
          });

  auto* panel = window_.approvalPanel();
  connect(window_.mapView(), &widgets::MapView::footholdClicked, this,
          [this](quint64 id, double x, double y) {
            if (session_) session_->editFoothold(id, x, y);
          });
  connect(panel, &widgets::StepApprovalPanel::approveRequested, this, [this](quint64 id) {
    if (session_) session_->approve(id);
  });
  connect(panel, &widgets::StepApprovalPanel::rejectRequested, this, [this](quint64 id) {
    if (session_) session_->reject(id, tr("rejected by %1").arg(options_.operator_id));
  });
  connect(panel, &widgets::StepApprovalPanel::resumeRequested, this, [this] {
    if (session_ && !timeline_) session_->resume();
  });
  connect(panel, &widgets::StepApprovalPanel::autoApproveChanged, this, [this](bool on) {
    if (session_) session_->setAutoApprove(on);
  });
}

void GroundStation::showTray(quint64 seed) {
  window_.showSamplingView();
  sampling_.simulateTray(seed);
}

QString GroundStation::newLogPath() const {
  QDir dir(options_.log_dir);
  dir.mkpath(".");
  return dir.filePath(
      QDateTime::currentDateTimeUtc().toString("'walk-'yyyyMMdd'T'HHmmss'Z.sqlite'"));
}

Refusal GroundStation::connectTo(const widgets::ConnectChoice& choice) {
  choice_ = choice;
  if (choice.source == widgets::ConnectChoice::Source::kLog) {
    openLog(choice.log_file);
    return {};
  }
  session_.reset();
  shown_.reset();
  timeline_.reset();
  window_.setReplay({});
  history_.clear();
  // The built-in simulator starts with the first walk, so that a launch
  // without one leaves no empty log behind; a rover is connected now.
  if (choice.source == widgets::ConnectChoice::Source::kDds) return openSession();
  simulator_.setGround(groundOf(choice));
  window_.setStatus(tr("Built-in simulator on %1: start a walk to connect")
                        .arg(QString::fromStdString(groundOf(choice).name(choice.seed))));
  return {};
}

Refusal GroundStation::openSession() {
  try {
    RoverConnection rover = choice_.source == widgets::ConnectChoice::Source::kDds
                                ? ddsConnection(std::uint32_t(choice_.domain), choice_.rover_id,
                                                choice_.key_file.toStdString())
                                : simulatorConnection(options_.simulator, choice_.seed,
                                                      options_.operator_id, groundOf(choice_));
    session_ = std::make_unique<WalkSession>(options_.ground, std::move(rover),
                                             newLogPath().toStdString());
  } catch (const std::exception& e) {
    return Refusal::because(std::string("Could not connect: ") + e.what());
  }
  connect(session_.get(), &WalkSession::changed, this, &GroundStation::showSession);
  connect(session_.get(), &WalkSession::eventNoted, this,
          [this](const QString& what) { window_.setStatus(tr("Walk: %1").arg(what)); });
  connect(
      session_.get(), &WalkSession::refused, this,
      [this](OperatorAction action, const QString& why) {
        if (action == OperatorAction::kEditFoothold) return window_.setStatus(why);
        if (action == OperatorAction::kAutoApprove)
          return window_.setStatus(tr("Walk: auto-approve refused the waiting step: %1").arg(why));
        if (action == OperatorAction::kGrasp)
          return window_.samplingPanel()->setGraspAnswer(tr("Not sent: %1").arg(why), false);
        window_.showError(why);
      });
  connect(session_.get(), &WalkSession::graspSent, this, [this] {
    window_.samplingPanel()->setGraspAnswer(
        tr("Grasp sent, signed by %1 and logged; waiting for the rover's answer")
            .arg(options_.operator_id),
        true);
  });
  connect(session_.get(), &WalkSession::graspAnswered, this,
          [this](bool accepted, const QString& reason) {
            window_.samplingPanel()->setGraspAnswer(
                accepted ? tr("The rover accepted the grasp")
                         : tr("The rover refused the grasp: %1").arg(reason),
                accepted);
          });
  connect(session_.get(), &WalkSession::scanMapped, &mesh_, &MeshController::addWalkScan);
  connect(session_.get(), &WalkSession::scanMapped, window_.rangeView(),
          &widgets::RangeImageView::setImage);
  shown_.reset();
  // The switch the operator sees decides, whenever the session was made.
  session_->setAutoApprove(window_.approvalPanel()->autoApproveSwitch()->isChecked());
  showSession();
  window_.setStatus(
      tr("Connected to %1; logging to %2")
          .arg(session_->linkDescription(), QString::fromStdString(session_->logPath().string())));
  return {};
}

void GroundStation::startWalk(int steps, const gait::Heading& heading) {
  if (timeline_ &&
      report(connectTo(choice_.source == widgets::ConnectChoice::Source::kLog ? launchedSimulator()
                                                                              : choice_)))
    return;
  if (!session_ && report(openSession())) return;
  auto* bar = window_.walkCommandBar();
  bar->setCommand(commandFor(steps, heading, bar->command().radius_m));
  session_start_s_ = link::utcNowS();
  history_.clear();
  // Each walk maps afresh: the last walk's map goes at once, before the
  // session's thread tells the new one.
  window_.mapView()->clear();
  window_.terrainView()->clear();
  mesh_.clearWalkScans();
  session_->start(steps, heading);
}

// Draws what changed since the state shown before: a view redrawn with
// what it already shows stalls the GUI for nothing.
void GroundStation::showSession() {
  if (!session_ || timeline_) return;
  const auto& state = session_->state();
  const WalkState* before = shown_.get();
  showWalkState();
  if (state.map && (!before || before->map != state.map)) {
    window_.mapView()->setMap(*state.map);
    window_.terrainView()->setMap(*state.map);
  }
  const bool proposal = !before || before->proposal_revision != state.proposal_revision;
  if (proposal) {
    window_.approvalPanel()->showProposal(state.pending);
    window_.mapView()->setProposal(state.pending);
  }
  if (proposal || !sameStance(before->reported, state.reported)) {
    const auto rover = drawn(state.pending ? std::optional(state.pending->from) : state.reported);
    window_.mapView()->setRover(rover);
    window_.terrainView()->setRover(rover, options_.ground.model, state.pending);
  }
  if (!before || before->rows != state.rows) window_.commandLog()->setRows(*state.rows);
  shown_ = session_->sharedState();
  if (!before) refreshTelemetry();  // then twice a second
  if (proposal && state.pending) emit proposalShown();
}

// What the walk is doing, and when it has stopped, why (a hold, a
// rejection, no step to propose, the link lost) in the executive's words.
void GroundStation::showWalkState() {
  const auto& state = session_->state();
  const auto phase = state.phase;
  QString text = QString::fromStdString(phaseName(phase));
  if (!state.rover_holding.empty())
    text += tr("; the rover HOLDS (%1)").arg(QString::fromStdString(state.rover_holding));
  const bool stopped = phase == executive::Phase::kSuspended;
  QString why;
  if (stopped) why = QString::fromStdString(state.suspended_because);
  if (phase == executive::Phase::kDone) why = tr("%1 step(s) walked").arg(state.steps_done);
  if (stopped && state.link_lost)
    why += tr("; LINK LOST (%1): Resume once the rover is heard again")
               .arg(QString::fromStdString(*state.link_lost));
  window_.approvalPanel()->setPhase(text, why, stopped);
  window_.approvalPanel()->setResumable(stopped && !state.link_lost);
}

// Between changes of phase the rover still moves: its pose, legs and the
// module timing follow its reports, and the link's age is shown twice a
// second.
void GroundStation::refreshTelemetry() {
  if (timeline_) return;
  if (!session_) {
    window_.setLinkStatus(tr("built-in simulator: no walk yet"), false);
    return;
  }
  const auto& state = session_->state();
  const double now = link::utcNowS();
  const auto sample = state.report.sample(options_.ground.model, now);
  if (sample && (history_.empty() || history_.back().stance.body.xy != sample->stance.body.xy ||
                 history_.back().stance.feet != sample->stance.feet ||
                 history_.back().force_n != sample->force_n)) {
    history_.push_back(*sample);
    window_.telemetry()->setHistory(history_, session_start_s_);
    if (!state.pending) window_.mapView()->setRover(drawn(sample->stance));
  }
  window_.telemetry()->setRover(sample);
  if (state.phase != executive::Phase::kIdle)
    window_.telemetry()->setModuleTiming(state.tasks, session_start_s_, now);
  window_.setAuthority(!state.authority.empty() && state.authority == state.console,
                       QString::fromStdString(state.authority_request));
  const auto age = session_->linkAgeS();
  const bool stale = !age || *age > 3.0;
  if (state.link_lost) {
    window_.setLinkStatus(
        tr("%1: LINK LOST, walk suspended (%2)")
            .arg(session_->linkDescription(), QString::fromStdString(*state.link_lost)),
        true);
    return;
  }
  window_.setLinkStatus(
      (age ? tr("%1: last data %2 s ago").arg(session_->linkDescription()).arg(*age, 0, 'f', 1)
           : tr("%1: no data yet").arg(session_->linkDescription())) +
          linkFigures(state, now),
      stale && state.phase != executive::Phase::kIdle);
}

// What a delay hides: how old the rover's state in view is (its own clock,
// UTC like the ground's), the command round trip, the commands not yet
// answered, the move under way, and who holds command authority.
QString GroundStation::linkFigures(const WalkState& state, double now_s) const {
  QStringList parts;
  if (state.report.body)
    parts << tr("state %1 s old").arg(now_s - state.report.body_time_s, 0, 'f', 1);
  if (state.round_trip_s) parts << tr("round trip %1 ms").arg(*state.round_trip_s * 1e3, 0, 'f', 0);
  parts << tr("%1 in flight").arg(state.commands_in_flight);
  // A suspended walk has held the rover already, which ends the move first.
  if (const auto& m = state.move_under_way)
    parts << tr("%1 under way %2 s (about %3 s%4)")
                 .arg(QString::fromStdString(m->type))
                 .arg(now_s - m->acknowledged_s, 0, 'f', 0)
                 .arg(m->modelled_s, 0, 'f', 0)
                 .arg(state.phase == executive::Phase::kSuspended
                          ? QString()
                          : tr("; held after %1 s").arg(m->due_s - m->acknowledged_s, 0, 'f', 0));
  const auto who = [&](const std::string& console) {
    return console == state.console ? tr("this console") : QString::fromStdString(console);
  };
  parts << (state.authority.empty() ? tr("authority: none")
                                    : tr("authority: %1").arg(who(state.authority)));
  if (!state.authority_request.empty())
    parts << tr("%1 asks for it").arg(who(state.authority_request));
  return " · " + parts.join(" · ");
}

void GroundStation::openLog(const QString& path) {
  if (opening_) return;  // one at a time
  const auto phase = session_ ? session_->state().phase : executive::Phase::kIdle;
  if (phase == executive::Phase::kExecuting || phase == executive::Phase::kAwaitingMoveEnd) {
    window_.showError(tr("The rover is moving: open the log once the move has ended."));
    emit replayFailed(tr("the rover is moving"));
    return;
  }
  opening_ = std::make_shared<Opening>();
  opening_->path = path;
  progress_dialog_ = std::make_unique<QProgressDialog>(
      tr("Building the terrain maps of %1…").arg(QFileInfo(path).fileName()), tr("Cancel"), 0, 1,
      &window_);
  progress_dialog_->setWindowTitle(tr("Opening mission log"));
  progress_dialog_->setMinimumDuration(300);
  connect(progress_dialog_.get(), &QProgressDialog::canceled, this,
          [opening = opening_] { opening->cancel = true; });
  progress_timer_.start(100);
  auto job = opening_;
  open_watcher_.setFuture(runInBackground([job]() -> std::shared_ptr<replay::MissionTimeline> {
    try {
      return std::make_shared<replay::MissionTimeline>(
          replay::MissionTimeline::build(job->path.toStdString(), [job](int done, int total) {
            job->done = done, job->total = total;
            return !job->cancel.load();
          }));
    } catch (const std::exception& e) {
      job->error = QString::fromUtf8(e.what());
      return nullptr;
    }
  }));
}

void GroundStation::finishOpening() {
  progress_timer_.stop();
  progress_dialog_.reset();
  const auto job = std::exchange(opening_, nullptr);
  auto timeline = open_watcher_.result();
  if (!timeline) {
    const QString why = tr("Could not open %1: %2").arg(job->path, job->error);
    if (!job->cancel) window_.showError(why);
    emit replayFailed(why);
    return;
  }
  session_.reset();  // a replay cannot command anything
  shown_.reset();
  timeline_ = std::make_unique<replay::MissionTimeline>(std::move(*timeline));
  replay_history_ = timeline_->samples(options_.ground.model);
  window_.setReplay(QFileInfo(job->path).fileName());
  // Only the log's state from here on: nothing of the live session stays.
  history_.clear();
  mesh_.clearWalkScans();
  window_.terrainView()->clear();
  window_.approvalPanel()->setResumable(false);
  window_.commandLog()->setRows(timeline_->rows());
  window_.telemetry()->setHistory(replay_history_, timeline_->firstS());
  window_.telemetry()->setModuleTiming(timeline_->tasks(), timeline_->firstS(), timeline_->lastS());
  window_.setLinkStatus(tr("replay: %1 scan(s), %2 unreadable message(s)")
                            .arg(timeline_->maps().size())
                            .arg(timeline_->unreadable()),
                        timeline_->unreadable() > 0);
  window_.setStatus(
      tr("Replaying %1 (%2)").arg(job->path, QString::fromStdString(timeline_->mission())));
  window_.timeline()->setRange(timeline_->firstS(), timeline_->lastS(), timeline_->marks());
  showReplayAt(window_.timeline()->time());
  emit replayReady();
}

void GroundStation::showReplayAt(double time_s) {
  if (!timeline_) return;
  const auto rover = timeline_->roverAt(time_s).sample(options_.ground.model, time_s);
  const auto stance = rover ? std::optional(rover->stance) : std::nullopt;
  auto pending = timeline_->pendingAt(time_s);
  if (pending && stance) pending->from = *stance;  // the rover stands still while it waits
  auto* map_view = window_.mapView();
  map_view->setProposal(pending && stance ? pending : std::nullopt);
  map_view->setRover(drawn(stance));
  if (const auto* m = timeline_->mapAt(time_s)) {
    map_view->setMap(m->map);
    window_.terrainView()->setMap(m->map);
    window_.rangeView()->setImage(m->scan);
  } else {
    window_.rangeView()->clear();
    map_view->setMap(terrain::ElevationMap(
        timeline_->maps().empty() ? GridSpec{} : timeline_->maps().front().map.grid()));
    window_.terrainView()->clear();
  }
  window_.terrainView()->setRover(drawn(stance), options_.ground.model, std::nullopt);
  auto* panel = window_.approvalPanel();
  panel->showProposal(pending);
  panel->setPhase(pending ? tr("replay: step %1 waits for a decision at this time").arg(pending->id)
                          : tr("replay: no step waits for a decision at this time"));
  window_.telemetry()->setRover(rover);
  window_.telemetry()->setCursor(time_s - timeline_->firstS());
  window_.commandLog()->setCurrentTime(time_s);
}

}  // namespace ambler::gs
