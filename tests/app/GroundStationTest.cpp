// Widget tests of the ground station's workflows against the
// simulator in this process, through the real wiring (GroundStation): a
// proposal reaches the panel with its interlocks, Approve moves the rover,
// Reject sends nothing, a click on the map moves the foothold and the
// interlocks judge it again, auto-approve is visible when on, a logged walk
// replays with the map of the time scrubbed to, exports write files, and
// each main view is saved as a screenshot. Needs a display (xvfb-run).
#include <vtkDataSet.h>
#include <vtkMapper.h>

#include <QApplication>
#include <QChartView>
#include <QCheckBox>
#include <QComboBox>
#include <QDir>
#include <QDockWidget>
#include <QFile>
#include <QLabel>
#include <QPushButton>
#include <QSemaphore>
#include <QSlider>
#include <QSpinBox>
#include <QStandardPaths>
#include <QTabWidget>
#include <QTableWidget>
#include <QTemporaryDir>
#include <QToolBar>
#include <QtTest/QtTest>
#include <random>
#include <set>

#include "app/gs/Background.h"
#include "app/gs/GroundStation.h"
#include "core/Resources.h"
#include "gait/RoverConfig.h"
#include "missionlog/MissionLog.h"
#include "rendering/SceneBuilders.h"
#include "rendering/VtkView.h"
#include "sim/CourseScene.h"
#include "sim/ObstacleCourse.h"
#include "sim/ProceduralTerrain.h"
#include "sim/StriperSim.h"
#include "sim/TerrainFamilies.h"
#include "tests/app/TestStation.h"
#include "tests/widgets/Hover.h"
#include "widgets/CommandLogView.h"
#include "widgets/ConnectDialog.h"
#include "widgets/DangerPanel.h"
#include "widgets/MapView.h"
#include "widgets/RangeImageView.h"
#include "widgets/SamplingPanel.h"
#include "widgets/StepApprovalPanel.h"
#include "widgets/TelemetryPanel.h"
#include "widgets/TerrainMeshPanel.h"
#include "widgets/TerrainView.h"
#include "widgets/TimelineBar.h"

using ambler::executive::Phase;
using ambler::gs::GroundStation;
using ambler::gs::WalkSession;
using ambler::widgets::MapView;
using ambler::widgets::StepApprovalPanel;

namespace {

// The cells of a marker sphere in the 3-D view (the path's start or goal).
long long markerCells() {
  auto sphere = ambler::rendering::makeSphere({0, 0, 0}, 1.0, {1, 1, 1});
  sphere->GetMapper()->Update();
  return sphere->GetMapper()->GetInput()->GetNumberOfCells();
}

using ambler::gs::test::options;
using ambler::test::hover;

// The station as an operator has it: the main window shown, its logs in a
// folder of the test's own.
struct Console {
  QTemporaryDir logs;
  GroundStation station{options(logs.path())};
  StepApprovalPanel& panel = *station.window().approvalPanel();
  MapView& map = *station.window().mapView();
  Console() {
    station.window().resize(1400, 900);
    station.window().show();
  }
  void start(int steps) { station.startWalk(steps); }
  // Asks for a scan as the toolbar does; whether it was shown.
  bool scan(int seed) {
    QSignalSpy scanned(&station.window(), &ambler::widgets::MainWindow::scanShown);
    emit station.window().scanRequested(quint64(seed));
    return scanned.wait(30000);
  }
  WalkSession& session() { return *station.session(); }
  void click(const Eigen::Vector2d& world) {
    QTest::mouseClick(&map, Qt::LeftButton, {}, map.widgetPointOf(world).toPoint());
  }
  int movesSent() {
    int n = 0;
    for (const auto& t : session().state().tasks)
      n += (t.name == "LegMove" || t.name == "BodyMove") && t.started_s > 0;
    return n;
  }
};

// Distinct colours in a sample of the image: a blank or one-colour grab
// has one or two.
int colourCount(const QImage& image) {
  std::set<QRgb> colours;
  for (int y = 0; y < image.height(); y += 3)
    for (int x = 0; x < image.width(); x += 3) colours.insert(image.pixel(x, y));
  return int(colours.size());
}

// Saves a grab of `widget` into the build tree's screenshots (docs/images
// keeps copies); an error when it looks blank or cannot be written.
QString screenshot(QWidget* widget, const QString& name) {
  QTest::qWait(300);  // let VTK and the charts paint
  const QDir dir(AMBLER_SCREENSHOT_DIR);
  const QImage shot = widget->grab().toImage();
  if (colourCount(shot) <= 20) return name + " looks blank";
  if (!dir.mkpath(".") || !shot.save(dir.filePath(name))) return "cannot write " + name;
  return {};
}

// Starts a one-step walk on `station`; whether the map of its first scan
// is of `family`'s ground of `seed` (rms under 5 cm) rather than of the
// obstacle course of that seed (more than twice that rms).
bool mapsTheFamily(GroundStation& station, ambler::sim::TerrainFamily family, std::uint64_t seed,
                   const ambler::sim::ScannerModel& scanner) {
  station.startWalk(1);
  if (!QTest::qWaitFor(
          [&] { return station.session() && station.session()->pending().has_value(); }, 30000))
    return false;
  const auto map = station.session()->state().map;
  if (!map || map->knownCount() < 1000) return false;
  auto rmsAgainst = [&](const ambler::sim::Terrain& truth) {
    double sum = 0.0;
    int n = 0;
    for (int r = 0; r < map->grid().rows; ++r)
      for (int c = 0; c < map->grid().cols; ++c) {
        if (!map->hasHeight(r, c)) continue;
        const Eigen::Vector2d p = map->grid().cellCenter(r, c);
        sum += std::pow(map->elevation(r, c) - truth.height(p.x(), p.y()), 2);
        ++n;
      }
    return std::sqrt(sum / n);
  };
  const double on_family =
      rmsAgainst(ambler::sim::ProceduralTerrain(ambler::sim::makeFamilyTerrain(family, seed)));
  const double on_course = rmsAgainst(ambler::sim::CourseScene(seed, scanner).terrain());
  qInfo("rms %.4f m against the family's ground, %.4f m against the course", on_family, on_course);
  return on_family < 0.05 && on_course > 2 * on_family;
}

}  // namespace

class GroundStationTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() { QStandardPaths::setTestModeEnabled(true); }

  void approvingAStepMovesTheRover() {
    Console c;
    QVERIFY(!c.panel.approveButton()->isEnabled());  // nothing to approve yet
    c.start(1);
    QTRY_VERIFY_WITH_TIMEOUT(c.panel.approveButton()->isEnabled(), 30000);
    QCOMPARE(c.panel.interlockTable()->rowCount(), 5);
    for (int row = 0; row < 5; ++row)
      QCOMPARE(c.panel.interlockTable()->item(row, 1)->text(), QString("passed"));
    const auto before = c.session().state().reported->body.xy;
    QTest::mouseClick(c.panel.approveButton(), Qt::LeftButton);
    QTRY_COMPARE_WITH_TIMEOUT(c.session().state().phase, Phase::kDone, 30000);
    const auto after = c.session().state().reported->body.xy;
    QVERIFY2((after - before).norm() > 0.1, "the rover did not move");
    QVERIFY(!c.panel.approveButton()->isEnabled());
    QVERIFY(c.session().linkAgeS().has_value());
    // What the status bar shows of the link: the round trip, nothing left
    // in flight, and this console in command (it sent the moves).
    QTRY_VERIFY_WITH_TIMEOUT(c.session().state().round_trip_s.has_value(), 5000);
    QVERIFY(*c.session().state().round_trip_s > 0 && *c.session().state().round_trip_s < 1.0);
    QTRY_COMPARE_WITH_TIMEOUT(c.session().state().commands_in_flight, std::size_t(0), 5000);
    QTRY_COMPARE_WITH_TIMEOUT(c.session().state().authority, c.session().state().console, 5000);
    QVERIFY(c.session().state().console.rfind("alice@", 0) == 0);
    // A second walk from where the first ended; the first walk's map goes
    // at once.
    QVERIFY(c.map.map().has_value());
    c.start(1);
    QVERIFY(!c.map.map().has_value());
    QTRY_VERIFY_WITH_TIMEOUT(c.panel.approveButton()->isEnabled(), 30000);
    QVERIFY((c.session().pending()->from.body.xy - after).norm() < 0.05);
  }

  // The link opens on the session's own thread: when it cannot, the
  // operator is told why, and later actions do nothing instead of failing.
  void aRoverThatCannotBeReachedIsRefusedNotFatal() {
    QTemporaryDir logs;
    ambler::gs::RoverConnection rover;
    rover.open = []() -> std::unique_ptr<ambler::link::Link> {
      throw std::runtime_error("no rover on the test's link");
    };
    rover.key = {"alice", std::vector<std::uint8_t>(32, 7)};
    rover.mission = "unreachable";
    WalkSession session(options(logs.path()).ground, std::move(rover),
                        QDir(logs.path()).filePath("walk.sqlite").toStdString());
    QSignalSpy refused(&session, &WalkSession::refused);
    QVERIFY(refused.wait(5000));
    QCOMPARE(refused.front().at(0).value<ambler::gs::OperatorAction>(),
             ambler::gs::OperatorAction::kConnect);
    QVERIFY2(refused.front().at(1).toString().contains("no rover on the test's link"),
             qPrintable(refused.front().at(1).toString()));
    session.start(1);
    session.approve(1);
    QTest::qWait(300);
    QCOMPARE(refused.size(), 1);
    QCOMPARE(session.state().phase, Phase::kIdle);
  }

  // The log is opened on the session's thread: a folder that cannot hold
  // it is refused by name, and nothing is sent to the rover unlogged.
  void aLogThatCannotBeWrittenIsRefusedNotFatal() {
    bool opened = false;
    ambler::gs::RoverConnection rover;
    rover.open = [&opened]() -> std::unique_ptr<ambler::link::Link> {
      opened = true;
      throw std::runtime_error("not to be opened without a log");
    };
    rover.key = {"alice", std::vector<std::uint8_t>(32, 7)};
    rover.mission = "unlogged";
    WalkSession session(options(QDir::tempPath()).ground, std::move(rover),
                        "/proc/no/such/walk.sqlite");
    QSignalSpy refused(&session, &WalkSession::refused);
    QVERIFY(refused.wait(5000));
    QCOMPARE(refused.front().at(0).value<ambler::gs::OperatorAction>(),
             ambler::gs::OperatorAction::kConnect);
    const QString why = refused.front().at(1).toString();
    QVERIFY2(why.contains("mission log") && why.contains("/proc/no/such/walk.sqlite"),
             qPrintable(why));
    session.start(1);
    QTest::qWait(300);
    QVERIFY(!opened);
    QCOMPARE(refused.size(), 1);
    QCOMPARE(session.state().phase, Phase::kIdle);
  }

  // The 3-D view cleared for a new walk draws the rover again as soon as
  // the walk's first map arrives, without waiting for the rover to move.
  void theThreeDViewDrawsTheRoverAgainOnceAMapFollowsAClear() {
    ambler::widgets::TerrainView view;
    view.resize(400, 300);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    ambler::terrain::ElevationMap map(ambler::GridSpec{-5.0, -5.0, 0.1, 100, 100});
    for (int r = 0; r < 100; ++r)
      for (int c = 0; c < 100; ++c) map.setKnown(r, c, 0.01 * (r % 7), 0.01);
    ambler::gait::Stance stance;
    for (int leg = 0; leg < ambler::gait::kLegCount; ++leg)
      stance.feet[std::size_t(leg)] = {leg < 3 ? -2.0 : 2.0, -1.0 + (leg % 3), 0.0};
    const ambler::widgets::RoverDisplay rover{stance, {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};
    view.setRover(rover, options({}).ground.model, std::nullopt);
    view.setMap(map);
    QTRY_VERIFY(view.view()->visibleCells() > 0);
    const long long with_rover = view.view()->visibleCells();
    view.clear();
    QTRY_COMPARE(view.view()->visibleCells(), 0LL);
    view.setMap(map);
    QTRY_COMPARE(view.view()->visibleCells(), with_rover);
  }

  void theMapShowsTheKnownCellsOfTheFirstScan() {
    Console c;
    c.start(1);
    QTRY_VERIFY_WITH_TIMEOUT(c.session().pending().has_value(), 30000);
    const QImage shot = c.map.grab().toImage();
    const QRect r = c.map.mapRect().toRect();
    int known = 0, unknown = 0;
    for (int y = r.top() + 1; y < r.bottom(); y += 2)
      for (int x = r.left() + 1; x < r.right(); x += 2) {
        const QColor p = shot.pixelColor(x, y);
        if (p == QColor(40, 40, 40))
          ++unknown;
        else
          ++known;
      }
    // The scanner sees ahead of the rover: the view holds both.
    QVERIFY2(known > 2000, qPrintable(QString::number(known)));
    QVERIFY(unknown > 2000);
    QVERIFY(c.session().state().map->knownCount() > 1000);
  }

  // On a terrain family in place of the course, chosen at launch
  // (ambler-gs --family) or in the Connect dialog, a walk maps that ground:
  // the map of its first scan matches the family's heights, not those of
  // the obstacle course of the same seed.
  void aWalkOnATerrainFamilyMapsThatGround() {
    using ambler::sim::TerrainFamily;
    QTemporaryDir logs;
    ambler::gs::StationOptions o = options(logs.path());
    o.seed = 3;
    o.simulated_ground.family = TerrainFamily::kRockField;
    GroundStation station(o);
    QVERIFY2(station.window().statusText().contains("rock field 3"),
             qPrintable(station.window().statusText()));
    QVERIFY(mapsTheFamily(station, TerrainFamily::kRockField, 3, o.scanner));

    ambler::widgets::ConnectDialog dialog(ambler::widgets::ConnectChoice{}, &station.window());
    auto* family = dialog.findChild<QComboBox*>();
    QVERIFY(family && family->isEnabled());
    family->setCurrentIndex(family->findText("Crater field"));
    QCOMPARE(dialog.choice().family, TerrainFamily::kCraterField);
    QVERIFY(!station.connectTo(dialog.choice()).refused());
    QVERIFY2(station.window().statusText().contains("crater field 1"),
             qPrintable(station.window().statusText()));
    QVERIFY(mapsTheFamily(station, TerrainFamily::kCraterField, 1, o.scanner));

    // A station launched on a terrain model has no family to choose.
    ambler::widgets::ConnectChoice on_model;
    on_model.on_terrain_model = true;
    dialog.setChoice(on_model);
    QVERIFY(!family->isEnabled());
  }

  void editingTheFootholdOnTheMapRechecksTheInterlocks() {
    Console c;
    c.start(6);
    c.station.window().showMapView();  // the operator's click on the tab
    // The first steps may move the body only: approve until a leg moves.
    for (int i = 0; i < 6; ++i) {
      QTRY_VERIFY_WITH_TIMEOUT(c.panel.approveButton()->isEnabled(), 30000);
      if (c.session().pending()->plan.leg >= 0) break;
      const auto approved = c.session().pending()->id;
      QTest::mouseClick(c.panel.approveButton(), Qt::LeftButton);
      QTRY_VERIFY_WITH_TIMEOUT(!c.session().pending() || c.session().pending()->id != approved,
                               30000);
    }
    QVERIFY(c.session().pending()->plan.leg >= 0);
    const Eigen::Vector2d planned = c.session().pending()->plan.foothold.head<2>();
    // The composite cost the planner chose it from reads out under the mouse,
    // and the leg's path ends there.
    c.map.setShown(MapView::Shown::kComposite);
    const QPoint at = c.map.widgetPointOf(planned).toPoint();
    // The readout needs the walk's cost maps from a worker; with other tests
    // keeping both cores busy it once took 14 s on CI: the same patience as
    // the other waits on the walk.
    QTRY_VERIFY2_WITH_TIMEOUT(
        [&] {
          hover(c.map, at);
          return c.map.readout().contains("composite cost");
        }(),
        qPrintable(c.map.readout()), 30000);
    const QString error = screenshot(&c.map, "terrain-map-composite-cost.png");
    QVERIFY2(error.isEmpty(), qPrintable(error));
    c.map.setShown(MapView::Shown::kElevation);
    // Four metres further ahead: out of the leg's reach.
    c.click(planned + Eigen::Vector2d(0, 4));
    QTRY_VERIFY(!c.panel.approveButton()->isEnabled());
    bool failed = false;
    for (int row = 0; row < c.panel.interlockTable()->rowCount(); ++row)
      failed |= c.panel.interlockTable()->item(row, 1)->text() == "FAILED";
    QVERIFY(failed);
    // Back where the planner put it: every interlock passes again.
    c.click(planned);
    QTRY_VERIFY(c.panel.approveButton()->isEnabled());
    QVERIFY((c.session().pending()->plan.foothold.head<2>() - planned).norm() < 0.1);
  }

  void rejectingAStepSendsNothing() {
    Console c;
    c.start(1);
    QTRY_VERIFY_WITH_TIMEOUT(c.panel.rejectButton()->isEnabled(), 30000);
    // (Xvfb has no window manager to activate the window for the shortcut.)
    QCOMPARE(c.panel.rejectButton()->shortcut(), QKeySequence(Qt::CTRL | Qt::Key_Backspace));
    QTest::mouseClick(c.panel.rejectButton(), Qt::LeftButton);
    QTRY_COMPARE_WITH_TIMEOUT(c.session().state().phase, Phase::kSuspended, 5000);
    QTest::qWait(300);
    QCOMPARE(c.movesSent(), 0);
    QVERIFY(!c.panel.rejectButton()->isEnabled());
  }

  // A stopped walk says why beside Approve, in the status bar and in the
  // table, as a sentence; Resume plans afresh and the walk goes on.
  void aStoppedWalkSaysWhyAndResumes() {
    Console c;
    auto& window = c.station.window();
    window.showSamplingView();  // where the operator happens to be
    c.start(2);
    QTRY_VERIFY_WITH_TIMEOUT(c.panel.rejectButton()->isEnabled(), 30000);
    QVERIFY2(window.samplingPanel()->isVisible(), "starting a walk switched the operator's tab");
    QVERIFY(!c.panel.resumeButton()->isEnabled());
    QTest::mouseClick(c.panel.rejectButton(), Qt::LeftButton);
    QTRY_COMPARE_WITH_TIMEOUT(c.session().state().phase, Phase::kSuspended, 5000);
    QTRY_VERIFY(c.panel.reasonLabel()->text().contains("step rejected by the operator"));
    QVERIFY(c.panel.phaseLabel()->text().contains("suspended"));
    QVERIFY2(window.statusText().contains("step rejected by the operator"),
             qPrintable(window.statusText()));
    const QString shot = screenshot(&c.panel, "walk-suspended.png");
    QVERIFY2(shot.isEmpty(), qPrintable(shot));
    auto* table = window.commandLog();
    bool event_row = false, raw_json = false;
    for (int row = 0; row < table->rowCount(); ++row) {
      event_row |= table->cellText(row, 1) == "ground" &&
                   table->cellText(row, 2).contains("step rejected by the operator");
      for (int col = 0; col < 5; ++col) raw_json |= table->cellText(row, col).contains('{');
    }
    QVERIFY2(event_row, "the stop is not in Events and commands");
    QVERIFY2(!raw_json, "a row of Events and commands shows raw JSON");

    QVERIFY(c.panel.resumeButton()->isEnabled());
    QTest::mouseClick(c.panel.resumeButton(), Qt::LeftButton);
    QTRY_VERIFY_WITH_TIMEOUT(c.panel.approveButton()->isEnabled(), 30000);
    QVERIFY(!c.panel.resumeButton()->isEnabled());
    QVERIFY(c.panel.reasonLabel()->text().isEmpty());
    // The stop and the resumption are in the mission log too.
    const ambler::missionlog::MissionLogReader log(c.session().logPath());
    int events = 0;
    for (const auto& p : log.products())
      events += p.kind == "event" && (p.parameters.find("rejected") != std::string::npos ||
                                      p.parameters.find("resumed") != std::string::npos);
    QCOMPARE(events, 2);
  }

  // The toolbar's path: three steps turning left in place, auto-approved.
  // The rover turns left where it stands, the walk's task says so, and the
  // decisions give the body's turn in degrees (a turn's body_u is radians).
  void theToolbarsTurnInPlaceTurnsTheRover() {
    using Path = ambler::widgets::WalkCommand::Path;
    Console c;
    auto& window = c.station.window();
    auto* bar = window.walkCommandBar();
    bar->setCommand({3, Path::kArcLeft, 12.0});
    QCOMPARE(bar->command().radius_m, 12.0);
    bar->setCommand({3, Path::kTurnLeft, 12.0});
    QCOMPARE(bar->command().path, Path::kTurnLeft);
    c.panel.autoApproveSwitch()->setChecked(true);
    window.walkAction()->trigger();
    QTRY_COMPARE_WITH_TIMEOUT(c.session().state().phase, Phase::kDone, 60000);
    const auto& state = c.session().state();
    const auto& body = state.reported->body;
    QVERIFY2(body.heading_rad > 10 * M_PI / 180, qPrintable(QString::number(body.heading_rad)));
    QVERIFY2(body.xy.norm() < 0.5, qPrintable(QString::number(body.xy.norm())));
    QVERIFY(std::any_of(state.tasks.begin(), state.tasks.end(), [](const auto& t) {
      return t.name == "walk 3 steps turning left in place";
    }));
    const auto& rows = c.session().commandRows();
    QVERIFY(std::any_of(rows.begin(), rows.end(), [](const auto& r) {
      const auto at = r.reason.find(", turns ");
      return r.what.rfind("approved", 0) == 0 && at != std::string::npos &&
             std::stod(r.reason.substr(at + 8)) > 5.0;
    }));
  }

  // Work that only feeds a view runs at nice 10, below the GUI thread and
  // the renderers yet never starved (SCHED_IDLE starved a worker holding
  // malloc's lock while the GUI thread waited for it); so do the OpenMP
  // threads such a job starts.
  void backgroundWorkRunsAtNiceTen() {
    using ambler::gs::runInBackground;
    const auto nice = [] { return getpriority(PRIO_PROCESS, id_t(gettid())); };
    // Waited for without waitForFinished(), which would run a job not yet
    // started here, on the GUI thread (below).
    auto job = runInBackground([&] { return std::make_pair(nice(), sched_getscheduler(0)); });
    QTRY_VERIFY(job.isFinished());
    QCOMPARE(job.result().first, 10);
    QCOMPARE(job.result().second, SCHED_OTHER);
    QThreadPool pool;
    auto team = runInBackground(&pool, [&] {
      int lowest = 20;
#pragma omp parallel num_threads(2) reduction(min : lowest)
      lowest = std::min(lowest, nice());
      return lowest;
    });
    QTRY_VERIFY(team.isFinished());
    QCOMPARE(team.result(), 10);
    // A job the GUI thread takes over while waiting for it (the one pool
    // thread is busy) runs at the GUI thread's own priority, and leaves it.
    QThreadPool one;
    one.setMaxThreadCount(1);
    QSemaphore busy;
    auto blocker = runInBackground(&one, [&] { busy.tryAcquire(1, 5000); });
    auto taken = runInBackground(&one, [&] { return nice(); });
    taken.waitForFinished();
    busy.release();
    blocker.waitForFinished();
    QCOMPARE(taken.result(), 0);
    QCOMPARE(nice(), 0);
  }

  // A walk started outside the toolbar (--walk, the soak) shows in it
  // what it walks: the steps, the path and an arc's radius; a straight
  // walk keeps the radius the operator set.
  void aWalkStartedElsewhereShowsInTheToolbar() {
    using Path = ambler::widgets::WalkCommand::Path;
    Console c;
    auto* bar = c.station.window().walkCommandBar();
    bar->setCommand({5, Path::kStraight, 7.0});
    c.station.startWalk(4, ambler::gait::Heading{-15.0});
    QCOMPARE(bar->command().steps, 4);
    QCOMPARE(bar->command().path, Path::kArcRight);
    QCOMPARE(bar->command().radius_m, 15.0);
    c.station.startWalk(2, ambler::gait::Heading{0.0, false});
    QCOMPARE(bar->command().path, Path::kTurnRight);
    c.start(1);
    QCOMPARE(bar->findChild<QSpinBox*>()->text(), QString("1 step"));
    c.start(9);
    QCOMPARE(bar->findChild<QSpinBox*>()->text(), QString("9 steps"));
    QCOMPARE(bar->command().steps, 9);
    QCOMPARE(bar->command().path, Path::kStraight);
    QCOMPARE(bar->command().radius_m, 15.0);
  }

  // Hold stops a walk in the middle of a step: the Hold goes out signed,
  // the rover says it holds, nothing more is sent, and the next walk ends
  // the hold.
  void holdStopsTheRoverMidStep() {
    Console c;
    auto* hold = c.station.window().holdAction();
    QVERIFY(hold->isEnabled());
    QCOMPARE(hold->shortcut(), QKeySequence(Qt::Key_Escape));
    c.start(3);
    c.panel.autoApproveSwitch()->setChecked(true);
    QTRY_VERIFY_WITH_TIMEOUT(c.movesSent() >= 1, 30000);
    hold->trigger();
    QTRY_COMPARE_WITH_TIMEOUT(c.session().state().phase, Phase::kSuspended, 5000);
    QTRY_VERIFY_WITH_TIMEOUT(!c.session().state().rover_holding.empty(), 5000);
    QVERIFY2(QString::fromStdString(c.session().state().rover_holding).contains("alice"),
             c.session().state().rover_holding.c_str());
    QTRY_VERIFY2(c.panel.phaseLabel()->text().contains("HOLDS"),
                 qPrintable(c.panel.phaseLabel()->text()));
    QVERIFY(c.panel.reasonLabel()->text().contains("Hold sent"));
    auto* table = c.station.window().commandLog();
    bool hold_accepted = false;
    QTRY_VERIFY_WITH_TIMEOUT(
        [&] {
          for (int row = 0; row < table->rowCount(); ++row)
            hold_accepted |= table->cellText(row, 2) == "Hold" &&
                             table->cellText(row, 3) == "accepted" &&
                             table->cellText(row, 1) == "alice";
          return hold_accepted;
        }(),
        5000);
    const int moves = c.movesSent();
    QTest::qWait(1500);
    QCOMPARE(c.movesSent(), moves);
    QVERIFY(c.session().state().steps_done < 3);
    c.start(1);
    QTRY_VERIFY_WITH_TIMEOUT(c.session().state().rover_holding.empty(), 10000);
  }

  void autoApproveIsVisibleAndWalksOnItsOwn() {
    Console c;
    c.start(2);
    c.panel.autoApproveSwitch()->setChecked(true);
    // The banner is red while auto-approve is on.
    const QImage shot = c.panel.banner()->grab().toImage();
    const QColor banner = shot.pixelColor(2, 2);
    QVERIFY2(banner.red() > 150 && banner.green() < 80, qPrintable(banner.name()));
    QTRY_COMPARE_WITH_TIMEOUT(c.session().state().phase, Phase::kDone, 60000);
    QCOMPARE(c.session().state().steps_done, 2);
    // Each step's scan reached the Terrain mesh tab and was registered; the
    // simulated rover's dead reckoning is close, so ICP moves it little.
    auto& mesh = c.station.mesh();
    QTRY_VERIFY_WITH_TIMEOUT(mesh.registeredScans().size() >= 2 && !mesh.registering(), 60000);
    QVERIFY(mesh.lastCorrection().translation().norm() < 0.05);
    // The Range image tab shows the walk's scans, not only a scan taken by hand.
    QVERIFY(c.station.window().rangeView()->image());
  }

  void theEventTableAnswersEachCommand() {
    Console c;
    c.start(1);
    QTRY_VERIFY_WITH_TIMEOUT(c.panel.approveButton()->isEnabled(), 30000);
    auto* table = c.station.window().commandLog();
    QTRY_VERIFY(table->rowCount() >= 2);  // Resume, AcquireScan
    bool scan_accepted = false;
    for (int row = 0; row < table->rowCount(); ++row)
      scan_accepted |= table->cellText(row, 2) == "AcquireScan range scanner" &&
                       table->cellText(row, 3) == "accepted" && table->cellText(row, 1) == "alice";
    QVERIFY(scan_accepted);
    QTest::mouseClick(c.panel.approveButton(), Qt::LeftButton);
    // The approved step's move, answered by the rover.
    const auto answeredMove = [table] {
      for (int row = 0; row < table->rowCount(); ++row)
        if (table->cellText(row, 2).startsWith("BodyMove") ||
            table->cellText(row, 2).startsWith("LegMove"))
          return table->cellText(row, 3) == "accepted";
      return false;
    };
    QTRY_VERIFY_WITH_TIMEOUT(answeredMove(), 30000);
    bool approved = false;
    for (int row = 0; row < table->rowCount(); ++row)
      approved |= table->cellText(row, 2).startsWith("approved proposal");
    QVERIFY(approved);
  }

  void aLoggedWalkReplaysWithTheMapOfTheTimeScrubbedTo() {
    Console c;
    c.panel.autoApproveSwitch()->setChecked(true);
    c.start(2);
    QTRY_COMPARE_WITH_TIMEOUT(c.session().state().phase, Phase::kDone, 60000);
    const QString log = QString::fromStdString(c.session().logPath().string());
    const auto live_known = c.session().state().map->knownCount();
    // The replay shows the rover as it reported itself.
    const Eigen::Vector2d end_xy =
        c.session().state().report.stance(options({}).ground.model)->body.xy;

    QSignalSpy ready(&c.station, &GroundStation::replayReady);
    c.station.openLog(log);
    QVERIFY(ready.wait(30000));
    const auto* timeline = c.station.timeline();
    QVERIFY(timeline && timeline->maps().size() >= 2);
    QVERIFY(c.station.window().timelineBar()->isVisible());
    QVERIFY(!c.station.window().walkAction()->isEnabled());  // a replay commands nothing
    auto* bar = c.station.window().timeline();
    QCOMPARE(c.map.map()->knownCount(), 0);  // the start: before the first scan
    const auto* range = c.station.window().rangeView();
    QVERIFY(!range->image());  // nor the live walk's last scan
    // Nor does the 3-D view keep the live walk's terrain then.
    QTRY_COMPARE(c.station.window().terrainView()->view()->visibleCells(), 0LL);

    // Drag the slider to just after the first scan: that scan's map.
    const auto& first = timeline->maps().front();
    const int at_first = int(std::ceil((first.time_s - timeline->firstS()) /
                                       (timeline->lastS() - timeline->firstS()) * 10000));
    bar->slider()->setValue(at_first);
    QVERIFY(bar->time() >= first.time_s && bar->time() < timeline->maps()[1].time_s);
    QCOMPARE(c.map.map()->knownCount(), first.map.knownCount());
    // The Range image tab shows that scan, where the logged correction put it.
    QVERIFY(range->image());
    QVERIFY(range->image()->sensor_to_world.isApprox(first.scan.sensor_to_world));
    QCOMPARE(range->image()->range, first.scan.range);
    const auto rows_then = c.station.window().commandLog()->rowCount();
    QVERIFY(rows_then > 0);

    // Stepping on reaches the last scan's map, the one the walk ended with.
    for (int i = 0; i < 200 && bar->time() < timeline->lastS(); ++i) bar->stepForward();
    QCOMPARE(bar->time(), timeline->lastS());
    QCOMPARE(c.map.map()->knownCount(), live_known);
    QVERIFY(c.map.map()->knownCount() > first.map.knownCount());
    const auto end = timeline->roverAt(bar->time()).stance(options({}).ground.model);
    QVERIFY(end);
    QVERIFY((end->body.xy - end_xy).norm() < 1e-9);
    QVERIFY(c.station.window().commandLog()->rowCount() >= rows_then);
  }

  // Scrubbed to while a step waited, the replay shows that step with its
  // interlocks, and nothing once it was approved; nothing live stays on
  // screen and nothing live can be commanded.
  void theReplayShowsTheStepThatWaitedAtTheTimeScrubbedTo() {
    Console c;
    c.start(1);
    QTRY_VERIFY_WITH_TIMEOUT(c.panel.approveButton()->isEnabled(), 30000);
    const quint64 waited = c.session().pending()->id;
    QTest::qWait(1000);  // the operator looks before deciding
    QTest::mouseClick(c.panel.approveButton(), Qt::LeftButton);
    QTRY_COMPARE_WITH_TIMEOUT(c.session().state().phase, Phase::kDone, 60000);
    const QString log = QString::fromStdString(c.session().logPath().string());

    QSignalSpy ready(&c.station, &GroundStation::replayReady);
    c.station.openLog(log);
    QVERIFY(ready.wait(30000));
    auto& window = c.station.window();
    for (QAction* live : {window.scanAction(), window.walkAction(), window.holdAction()})
      QVERIFY2(!live->isEnabled(), qPrintable(live->text()));
    QVERIFY(!c.panel.isEnabled());
    // Not the live mode's banner: nothing in a replay waits for the operator.
    QCOMPARE(c.panel.banner()->text(),
             QString("Replay: the decisions the log holds; nothing is sent"));

    // The approval's row gives the time the step stopped waiting.
    const auto& rows = c.station.timeline()->rows();
    const auto approved = std::find_if(rows.begin(), rows.end(), [&](const auto& r) {
      return r.what == "approved proposal " + std::to_string(waited);
    });
    QVERIFY(approved != rows.end());
    auto* bar = window.timeline();
    bar->setTime(approved->time_s - 0.5);
    QVERIFY2(c.panel.phaseLabel()->text().contains(QString("step %1 waits").arg(waited)),
             qPrintable(c.panel.phaseLabel()->text()));
    QCOMPARE(c.panel.interlockTable()->rowCount(), 5);
    bar->setTime(approved->time_s + 0.01);
    QCOMPARE(c.panel.interlockTable()->rowCount(), 0);
    QVERIFY(c.panel.phaseLabel()->text().contains("no step waits"));
  }

  void exportsWriteTheMapLayersPlotsAndTable() {
    Console c;
    c.start(1);
    QTRY_VERIFY_WITH_TIMEOUT(c.panel.approveButton()->isEnabled(), 30000);
    QTemporaryDir out;
    auto& w = c.station.window();
    QCOMPARE(w.exportMapLayers(out.path()).why(), std::string());
    for (const char* f : {"elevation.tif", "sigma.tif", "state.tif"})
      QVERIFY2(QFile::exists(QDir(out.path()).filePath(f)), f);
    QCOMPARE(w.exportPlots(out.path()).why(), std::string());
    QVERIFY(QImage(QDir(out.path()).filePath("module-timing.png")).width() > 100);
    QVERIFY(QImage(QDir(out.path()).filePath("foot-heights.png")).width() > 100);
    QVERIFY(QImage(QDir(out.path()).filePath("foot-loads.png")).width() > 100);
    const QString csv = QDir(out.path()).filePath("commands.csv");
    QCOMPARE(w.exportTable(csv).why(), std::string());
    QFile file(csv);
    QVERIFY(file.open(QIODevice::ReadOnly));
    const auto lines = QString::fromUtf8(file.readAll()).split('\n', Qt::SkipEmptyParts);
    QCOMPARE(lines.front(), QString("time_s,operator,command,answer,reason"));
    QCOMPARE(lines.size(), w.commandLog()->rowCount() + 1);
    // A folder that cannot be written is named in the error, not a crash.
    QVERIFY(QString::fromStdString(w.exportTable("/proc/no/such/commands.csv").why())
                .contains("/proc/no/such"));
  }

  // Rock sampling: a click on a seed in the tray's image outlines the rock,
  // fits it (close to the simulator's rock) and approving sends a signed,
  // logged Grasp.
  void samplingAFittedRockSendsASignedGrasp() {
    Console c;
    QSignalSpy shown(&c.station.sampling(), &ambler::gs::SamplingController::trayShown);
    c.station.showTray(3);
    QVERIFY(shown.wait(30000));
    auto& panel = *c.station.window().samplingPanel();
    QVERIFY(!panel.seeds().empty());
    QVERIFY(!panel.approveButton()->isEnabled());
    const auto seed = panel.seeds().front().pixel;
    QTest::mouseClick(panel.imageView(), Qt::LeftButton, {},
                      panel.viewPointOf(seed.y(), seed.x()).toPoint());
    QTRY_VERIFY_WITH_TIMEOUT(panel.sample().has_value(), 10000);  // fitted on a worker
    // The rock under the seed, in the same simulated tray.
    const ambler::sim::ProceduralTerrain tray(
        ambler::sim::makeWorkArea({.seed = 3, .burial_min = 0.0, .burial_max = 0.5}));
    const auto truth = ambler::sim::simulateStriper(tray, ambler::sim::StriperModel{}, 3);
    const int label = truth.labels(int(std::lround(seed.y())), int(std::lround(seed.x())));
    QVERIFY(label != ambler::sim::kLabelGround && label != ambler::sim::kLabelNothing);
    const auto& rock =
        std::get<ambler::sim::Rock>(tray.description().features[std::size_t(label - 1)]).shape;
    const auto& fit = panel.sample()->fit.shape;
    QVERIFY2((fit.pose.translation() - rock.pose.translation()).head<2>().norm() < 0.01,
             "the fit is not on the rock clicked");
    QVERIFY(panel.info()->text().contains("Superquadric"));
    QTRY_VERIFY(panel.approveButton()->isEnabled());  // after the contour has grown on screen
    const QString error = screenshot(&panel, "rock-sampling.png");
    QVERIFY2(error.isEmpty(), qPrintable(error));

    QTest::mouseClick(panel.approveButton(), Qt::LeftButton);
    QVERIFY(c.station.session());
    // Sent (the answer may follow before the next look).
    QTRY_VERIFY(panel.info()->text().contains("Grasp sent") ||
                panel.info()->text().contains("The rover"));
    // What the rover answered, not what was hoped for.
    QTRY_VERIFY_WITH_TIMEOUT(panel.info()->text().contains("The rover refused the grasp"), 5000);
    QVERIFY2(panel.info()->text().contains("manipulator"), qPrintable(panel.info()->text()));
    const auto& rows = c.session().commandRows();
    auto row = std::find_if(rows.begin(), rows.end(),
                            [](const auto& r) { return r.what.rfind("Grasp", 0) == 0; });
    QVERIFY(row != rows.end());
    QCOMPARE(QString::fromStdString(row->who), QString("alice"));
    QVERIFY(std::any_of(rows.begin(), rows.end(),
                        [](const auto& r) { return r.what == "approved grasp"; }));
    // In the mission log, signed: the rover verified it and answered (this
    // simulated Ambler, like the real one, has no manipulator).
    QTRY_VERIFY_WITH_TIMEOUT(
        std::any_of(c.session().commandRows().begin(), c.session().commandRows().end(),
                    [](const auto& r) {
                      return r.what.rfind("Grasp", 0) == 0 && !r.outcome.empty() &&
                             r.reason.find("signature") == std::string::npos;
                    }),
        5000);
    const ambler::missionlog::MissionLogReader log(c.session().logPath());
    QCOMPARE(log.summary().to_rover.at("Grasp"), 1L);
  }

  // The last scan as a triangle mesh, built on a worker once the tab is
  // shown; two clicks plan a path that keeps off triangles beyond the
  // slope limit, simplified within 5 % of its cost.
  void meshPanelPlansAPathBetweenTwoClicks() {
    Console c;
    auto& w = c.station.window();
    auto& mesh = c.station.mesh();
    QVERIFY(c.scan(1));
    QVERIFY(!mesh.mesh());  // not meshed while nobody looks
    const long long scene = w.terrainView()->view()->visibleCells();
    QSignalSpy built(&mesh, &ambler::gs::MeshController::meshBuilt);
    w.showMeshView();
    QVERIFY(built.wait(30000));
    QVERIFY(mesh.mesh()->size() > 100);
    auto& panel = *w.meshPanel();
    // The 3-D view draws the mesh, then the path over it too (each once the
    // event loop has rebuilt the scene).
    const long long with_mesh = scene + (long long)(mesh.mesh()->size());  // a line each
    QTRY_COMPARE(w.terrainView()->view()->visibleCells(), with_mesh);
    QTest::mouseClick(panel.meshView(), Qt::LeftButton, {},
                      panel.viewPointOf({0.0, 7.0}).toPoint());
    QVERIFY(panel.readout().contains("click the goal"));
    QSignalSpy planned(&mesh, &ambler::gs::MeshController::pathPlanned);
    QTest::mouseClick(panel.meshView(), Qt::LeftButton, {},
                      panel.viewPointOf({1.0, 17.0}).toPoint());
    QVERIFY(planned.wait(30000));
    QVERIFY2(mesh.path() && mesh.path()->found, qPrintable(panel.readout()));
    const auto& path = *mesh.path();
    for (int t : path.triangles) QVERIFY(mesh.mesh()->slopeRad(t) <= 20 * M_PI / 180 + 1e-9);
    QVERIFY(path.simplified.size() < path.raw.size());
    QVERIFY(path.simplified_cost <= 1.05 * path.raw_cost);
    QVERIFY((path.simplified.back().head<2>() - Eigen::Vector2d(1, 17)).norm() < 0.2);
    QVERIFY(panel.readout().contains("Path:"));
    // One polyline, and the start's and goal's markers.
    QTRY_COMPARE(w.terrainView()->view()->visibleCells(), with_mesh + 1 + 2 * markerCells());
    for (const auto& [widget, name] : {std::pair<QWidget*, QString>{&panel, "terrain-mesh.png"},
                                       {w.terrainView(), "3d-view-mesh-path.png"}}) {
      const QString error = screenshot(widget, name);
      QVERIFY2(error.isEmpty(), qPrintable(error));
    }
    // Another cost plans again.
    panel.costBox()->setCurrentIndex(2);
    QVERIFY(planned.wait(30000));
    QVERIFY(mesh.path() && mesh.path()->found);
    QVERIFY(panel.readout().contains("Path:"));
  }

  // The same from the 3-D view: a click on the ground sets the path's
  // start, marked there, and the next its goal; the path is planned
  // between the points picked.
  void clicksInThe3dViewPlanAPath() {
    Console c;
    auto& w = c.station.window();
    auto& mesh = c.station.mesh();
    QVERIFY(c.scan(1));
    QSignalSpy built(&mesh, &ambler::gs::MeshController::meshBuilt);
    w.showMeshView();
    QVERIFY(built.wait(30000));
    auto* view = w.terrainView()->view();
    const long long with_mesh = view->visibleCells() + (long long)(mesh.mesh()->size());
    QTRY_COMPARE(view->visibleCells(), with_mesh);
    QSignalSpy picked(w.terrainView(), &ambler::widgets::TerrainView::groundPicked);
    auto click = [&](const Eigen::Vector2d& xy) {
      const auto at = view->widgetPointOf({xy.x(), xy.y(), 0.0});
      QVERIFY(at && view->rect().contains(at->toPoint()));
      QTest::mouseClick(view, Qt::LeftButton, {}, at->toPoint());
      QVERIFY(picked.wait(5000));
    };
    click({0.0, 7.0});
    const auto start = picked.takeFirst().at(0).value<Eigen::Vector2d>();
    QVERIFY((start - Eigen::Vector2d(0, 7)).norm() < 0.5);  // the ground is not at z = 0
    QCOMPARE(*mesh.start(), start);
    QVERIFY(!mesh.goal());
    QVERIFY(w.meshPanel()->readout().contains("click the goal"));
    const long long sphere = markerCells();
    QTRY_COMPARE(view->visibleCells(), with_mesh + sphere);  // the start's marker
    QSignalSpy planned(&mesh, &ambler::gs::MeshController::pathPlanned);
    click({1.0, 17.0});
    const auto goal = picked.takeFirst().at(0).value<Eigen::Vector2d>();
    QVERIFY(planned.wait(30000));
    QVERIFY2(mesh.path() && mesh.path()->found, qPrintable(w.meshPanel()->readout()));
    QVERIFY((mesh.path()->simplified.front().head<2>() - start).norm() < 0.2);
    QVERIFY((mesh.path()->simplified.back().head<2>() - goal).norm() < 0.2);
    // The path's polyline and both markers.
    QTRY_COMPARE(view->visibleCells(), with_mesh + 1 + 2 * sphere);
    const QString error = screenshot(w.terrainView(), "3d-view-path-picked.png");
    QVERIFY2(error.isEmpty(), qPrintable(error));
  }

  // A click in the 3-D view before the Terrain mesh tab was ever shown
  // builds the mesh there and then; the clicks after it plan the path.
  void aClickInThe3dViewBeforeAnyMeshBuildsOne() {
    Console c;
    auto& w = c.station.window();
    auto& mesh = c.station.mesh();
    QVERIFY(c.scan(1));
    auto* view = w.terrainView()->view();
    const auto at = view->widgetPointOf({0.0, 7.0, 0.0});
    QVERIFY(at && view->rect().contains(at->toPoint()));
    QSignalSpy built(&mesh, &ambler::gs::MeshController::meshBuilt);
    QTest::mouseClick(view, Qt::LeftButton, {}, at->toPoint());
    QVERIFY(built.wait(30000));
    QVERIFY(!w.meshPanel()->isVisible());
    QVERIFY(!mesh.start());  // that click only asked for the mesh
    QSignalSpy picked(w.terrainView(), &ambler::widgets::TerrainView::groundPicked);
    QTRY_VERIFY(!mesh.outlines().empty());
    QTest::qWait(100);  // the outlines reach the view by a queued rebuild
    QTest::mouseClick(view, Qt::LeftButton, {}, at->toPoint());
    QVERIFY(picked.wait(5000));
    QVERIFY(mesh.start());
  }

  // A walk's scans, the second put 0.15 m and 2 degrees off by dead
  // reckoning: ICP in the background takes it back to within 3 cm and
  // 0.2 degrees, the mesh is of both, and the 3-D view draws both scans.
  void meshPanelRegistersAndMergesAWalksScans() {
    Console c;
    auto& w = c.station.window();
    QVERIFY(c.scan(1));  // the ground under the 3-D view
    w.showMeshView();
    auto& panel = *w.meshPanel();
    auto& mesh = c.station.mesh();
    const auto model = ambler::sim::readScannerModel(ambler::findResource("config/scanner.json"));
    const ambler::sim::CourseScene here(1, model), on(1, model, {0.3, 2.0}, 5 * M_PI / 180);
    const auto first = here.scan(1);
    auto second = on.scan(2);
    const Eigen::Isometry3d error = Eigen::Translation3d(0.15, -0.1, 0.02) *
                                    Eigen::AngleAxisd(2 * M_PI / 180, Eigen::Vector3d::UnitZ());
    second.sensor_to_world = error * second.sensor_to_world;
    const long long before = w.terrainView()->view()->visibleCells();
    mesh.addWalkScan(first);
    QCOMPARE(mesh.registeredScans().size(), std::size_t(1));  // the reference
    QTRY_VERIFY_WITH_TIMEOUT(mesh.mesh(), 30000);
    const auto single = mesh.mesh()->size();
    mesh.addWalkScan(second);
    QVERIFY(mesh.registering());
    QVERIFY(panel.readout().contains("Registering 1 scan"));
    QTRY_VERIFY_WITH_TIMEOUT(mesh.registeredScans().size() == 2, 60000);
    const Eigen::Isometry3d residual = mesh.lastCorrection() * error;
    QVERIFY2(residual.translation().norm() < 0.03,
             qPrintable(QString::number(residual.translation().norm())));
    QVERIFY(Eigen::AngleAxisd(residual.linear()).angle() < 0.2 * M_PI / 180);
    QVERIFY2(panel.readout().contains("2 walk scans registered and merged"),
             qPrintable(panel.readout()));
    QTRY_VERIFY_WITH_TIMEOUT(mesh.mesh(), 30000);
    QVERIFY(mesh.mesh()->size() > single);  // the second view adds ground
    QTRY_VERIFY(w.terrainView()->view()->visibleCells() > before);
    for (const auto& [widget, name] :
         {std::pair<QWidget*, QString>{&panel, "terrain-mesh-merged.png"},
          {w.terrainView(), "3d-view-registered-scans.png"}}) {
      const QString error_text = screenshot(widget, name);
      QVERIFY2(error_text.isEmpty(), qPrintable(error_text));
    }
    // A scan taken on demand replaces the walk's.
    QVERIFY(c.scan(1));
    QVERIFY(mesh.registeredScans().empty());
  }

  // A camera image of sand with a rock field across the way ahead: the
  // Danger map tab shows D, the route around the rocks and the sensing plan.
  void dangerPanelShowsTheRouteAroundARock() {
    Console c;
    auto& w = c.station.window();
    auto& panel = *w.dangerPanel();
    std::mt19937 rng(5);
    std::normal_distribution<float> sand(200.0f, 3.0f), rock(90.0f, 40.0f);
    ambler::io::FloatImage image(480, 640);
    for (int r = 0; r < 480; ++r)
      for (int col = 0; col < 640; ++col)
        image(r, col) = (r >= 300 && r < 330 && col >= 250 && col < 420) ? rock(rng) : sand(rng);
    auto& danger = c.station.danger();
    QVERIFY2(!danger.analyse(image, "rocks ahead").refused(), qPrintable(panel.readout()));
    QVERIFY(danger.route() && danger.route()->found);
    QVERIFY(panel.route() && panel.route()->way_areas.size() == danger.route()->way_areas.size());
    QVERIFY(!danger.route()->way_areas.empty());
    QVERIFY2(panel.readout().contains("F: turn to the destination"), qPrintable(panel.readout()));
    w.showDangerView();
    const QString error = screenshot(&panel, "danger-map.png");
    QVERIFY2(error.isEmpty(), qPrintable(error));
    const auto missing = danger.open("/nonexistent/camera.png");
    QVERIFY(QString::fromStdString(missing.why()).contains("does not exist"));
    QVERIFY(panel.readout().contains("does not exist"));
  }

  // Screenshots of each main view into the build tree (docs/images keeps
  // copies), each checked not to be blank.
  void screenshotsOfEachMainView() {
    Console c;
    auto& w = c.station.window();
    QVERIFY(c.scan(1));
    auto save = [&](QWidget* widget, const QString& name) {
      const QString error = screenshot(widget, name);
      QVERIFY2(error.isEmpty(), qPrintable(error));
    };
    save(w.rangeView(), "range-image.png");
    c.start(1);
    QTRY_VERIFY_WITH_TIMEOUT(c.panel.approveButton()->isEnabled(), 30000);
    save(&w, "main-window.png");
    const auto* layers = c.map.findChild<QComboBox*>();
    QVERIFY(layers);
    QVERIFY2(layers->width() >= layers->sizeHint().width(),
             "the map's layer box cuts its names short");
    save(&c.map, "terrain-map.png");
    save(w.terrainView(), "3d-view.png");
    save(&c.panel, "step-approval.png");
    QTest::mouseClick(c.panel.approveButton(), Qt::LeftButton);
    QTRY_COMPARE_WITH_TIMEOUT(c.session().state().phase, Phase::kDone, 30000);
    QTest::qWait(600);  // a telemetry refresh
    save(w.telemetry(), "telemetry.png");
    // The force sensors' loads, as the table shows them, carry the weight.
    double load_kn = 0;
    for (int leg = 0; leg < ambler::gait::kLegCount; ++leg)
      load_kn += w.telemetry()->legTable()->item(leg, 2)->text().toDouble();
    QVERIFY2(std::abs(load_kn - options({}).ground.model.mass_kg * 9.81e-3) < 0.05,
             qPrintable(QString::number(load_kn)));
    // Its dock shares a tab with the telemetry: bring it to the front.
    qobject_cast<QDockWidget*>(w.commandLog()->parentWidget())->raise();
    QTRY_VERIFY(w.commandLog()->isVisible());
    save(w.commandLog(), "events.png");
    QSignalSpy ready(&c.station, &GroundStation::replayReady);
    c.station.openLog(QString::fromStdString(c.session().logPath().string()));
    QVERIFY(ready.wait(30000));
    w.timeline()->setTime(w.timeline()->time() +
                          0.6 * (c.station.timeline()->lastS() - c.station.timeline()->firstS()));
    save(&w, "replay.png");
  }
};

QTEST_MAIN(GroundStationTest)
#include "GroundStationTest.moc"
