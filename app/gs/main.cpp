// ambler-gs: the operator's ground station. Starts against the built-in
// simulator, so a new user sees a scan and its terrain on first launch.
#include <malloc.h>
#include <QApplication>
#include <QCheckBox>
#include <QCommandLineParser>
#include <QElapsedTimer>
#include <QMessageBox>
#include <QStandardPaths>
#include <QStringList>
#include <QSurfaceFormat>
#include <QTimer>

#include <Eigen/Core>
#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "app/gs/EventLoopWatchdog.h"
#include "app/gs/GroundStation.h"
#include "app/gs/Soak.h"
#include "core/Memory.h"
#include "core/Resources.h"
#include "gait/RoverConfig.h"
#include "rendering/VtkView.h"
#include "sim/TerrainFamilies.h"
#include "widgets/SamplingPanel.h"
#include "widgets/StepApprovalPanel.h"
#include "widgets/TerrainView.h"

namespace {

// Saves the window 800 ms after the first call (the views have painted),
// then quits with `status` (1 if it could not save). The 3-D view draws on
// its own thread, a frame of the full scene taking up to 0.4 s on a loaded
// machine: the shot waits for a frame that holds what was sent to it.
void screenshotOnce(ambler::widgets::MainWindow& window, const QString& path, int status = 0) {
  static bool shot = false;
  if (std::exchange(shot, true)) return;
  QTimer::singleShot(800, &window, [&window, path, status] {
    window.terrainView()->view()->renderedImage();
    const bool saved = window.grab().save(path);
    std::cout << (saved ? "saved " : "could not save ") << path.toStdString() << std::endl;
    QApplication::exit(saved ? status : 1);
  });
}

// An error the GUI showed, on stderr: the launches that quit by themselves
// end on it, as what they wait for will not come (a terrain model refused).
void printError(const QString& message) {
  std::cerr << "ambler-gs: error: " << message.toStdString() << std::endl;
}

// The median time of ten frames of the 3-D view at one level of detail
// (VTK's render on the view's render thread and reading it back), and the
// cells drawn.
std::pair<double, long long> frameTimes(ambler::rendering::VtkView* view, bool moving) {
  view->setCameraMoving(moving);
  std::vector<double> ms;
  for (int i = 0; i < 10; ++i) {
    QElapsedTimer timer;
    timer.start();
    view->renderedImage();
    ms.push_back(double(timer.nsecsElapsed()) / 1e6);
  }
  std::nth_element(ms.begin(), ms.begin() + 5, ms.end());
  const long long cells = view->visibleCells();
  view->setCameraMoving(false);
  return {ms[5], cells};
}

void printStalls(const ambler::gs::StallSummary& s, std::ostream& out) {
  out << "\"ticks\": " << s.ticks << ", \"stall_p50_ms\": " << s.p50_ms
      << ", \"stall_p99_ms\": " << s.p99_ms << ", \"stall_max_ms\": " << s.max_ms
      << ", \"stalls_20ms_or_more\": " << s.over_20ms
      << ", \"stalls_50ms_or_more\": " << s.over_50ms << ", \"worst_at_s\": " << s.worst_at_s;
}

// The scripted session of --measure-responsiveness: an auto-approved walk
// of `steps` steps, then a rock fit on a simulated tray and the terrain
// mesh of the last scan, with the event loop's stalls measured throughout;
// prints them as JSON and quits.
void measureResponsiveness(ambler::gs::GroundStation& station,
                           ambler::gs::EventLoopWatchdog& watchdog, int steps) {
  auto& window = station.window();
  auto started = std::make_shared<QElapsedTimer>();
  QObject::connect(&window, &ambler::widgets::MainWindow::scanShown, &station, [&, started, steps] {
    if (started->isValid()) return;
    started->start();
    watchdog.start();
    window.approvalPanel()->autoApproveSwitch()->setChecked(true);
    station.startWalk(steps);
  });
  QObject::connect(&window, &ambler::widgets::MainWindow::errorShown, &station,
                   [started](const QString& message) {
                     if (started->isValid()) return;  // before the walk only: no scan will come
                     printError(message);
                     QApplication::exit(1);
                   });
  auto* poll = new QTimer(&station);
  QObject::connect(poll, &QTimer::timeout, &station, [&, started, poll] {
    const auto* session = station.session();
    if (!started->isValid() || !session) return;
    const auto phase = session->state().phase;
    if (phase != ambler::executive::Phase::kDone && phase != ambler::executive::Phase::kSuspended)
      return;
    poll->stop();
    const double walk_s = double(started->elapsed()) / 1000.0;
    const int done = session->state().steps_done;
    // The 3-D view of the walk's whole traverse map, timed outside the
    // stalls' count.
    watchdog.stop();
    auto* view = window.terrainView()->view();
    const auto still = frameTimes(view, false), moving = frameTimes(view, true);
    // Once the events that piled up while the timing held the GUI thread
    // are handled: that backlog is the measurement's, not the console's.
    QMetaObject::invokeMethod(
        &watchdog, [&watchdog] { watchdog.resume(); }, Qt::QueuedConnection);
    QObject::connect(&station.sampling(), &ambler::gs::SamplingController::trayShown, &station,
                     [&] {
                       auto* sampling = window.samplingPanel();
                       if (!sampling->seeds().empty())
                         station.sampling().fitAt(sampling->seeds().front().pixel.y(),
                                                  sampling->seeds().front().pixel.x(), true);
                       window.showMeshView();
                     });
    station.showTray(3);
    QTimer::singleShot(3000, &station, [&, walk_s, done, started, still, moving] {
      watchdog.stop();
      std::cout << "{\"steps\": " << done << ", \"walk_s\": " << walk_s
                << ", \"session_s\": " << double(started->elapsed()) / 1000.0
                << ", \"map_frame_ms_still\": " << still.first
                << ", \"map_cells_still\": " << still.second
                << ", \"map_frame_ms_moving\": " << moving.first
                << ", \"map_cells_moving\": " << moving.second << ", ";
      printStalls(watchdog.summary(), std::cout);
      std::cout << "}" << std::endl;
      QApplication::exit(0);
    });
  });
  poll->start(100);
}

// Without a display Qt aborts at QApplication. --help and --version need
// none, so they get the offscreen platform; anything else is refused with
// what to do, exit code 2.
bool haveADisplayOrNeedNone(int argc, char** argv) {
  if (qEnvironmentVariableIsSet("QT_QPA_PLATFORM") || qEnvironmentVariableIsSet("DISPLAY") ||
      qEnvironmentVariableIsSet("WAYLAND_DISPLAY"))
    return true;
  bool help = false;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a(argv[i]);
    if (a == "-platform") return true;
    help = help || a == "-h" || a == "--help" || a == "--help-all" || a == "-v" || a == "--version";
  }
  if (help) {
    qputenv("QT_QPA_PLATFORM", "offscreen");
    return true;
  }
  std::cerr << "ambler-gs: no display (neither DISPLAY nor WAYLAND_DISPLAY is set): run it in a "
               "desktop session, under xvfb-run, or with QT_QPA_PLATFORM=offscreen"
            << std::endl;
  return false;
}

// What the command line asks of this launch.
struct LaunchOptions {
  quint64 seed = 1;
  int walk_steps = 0;  // 0: no walk at launch
  int soak_steps = 0;  // 0: no soak
  QString log_dir, screenshot, replay, dtm;
  ambler::sim::TerrainFamily family = ambler::sim::TerrainFamily::kCourse;
  std::optional<Eigen::Vector2d> dtm_centre;  // in the DTM's CRS [m]; default its centre
  bool startup_time = false, responsiveness = false;
};

// False, after saying why, when the command line combines options of which
// one would wait for what the other never shows, or quit before it.
bool optionsCombine(const QCommandLineParser& parser) {
  struct Rule {
    const char* option;
    const char* why;
    std::vector<const char*> excluded;
  };
  static const Rule rules[] = {
      {"soak",
       "walks courses 1-10 by itself",
       {"replay", "dtm", "family", "walk", "screenshot", "startup-time", "measure-responsiveness"}},
      {"replay",
       "shows the log alone",
       {"walk", "dtm", "family", "startup-time", "measure-responsiveness"}},
      {"dtm", "simulates on the terrain model", {"family"}},
      {"startup-time", "quits at the first scan", {"screenshot", "measure-responsiveness"}},
      {"measure-responsiveness", "quits after its own walk", {"screenshot"}}};
  for (const auto& rule : rules) {
    if (!parser.isSet(rule.option)) continue;
    for (const char* other : rule.excluded)
      if (parser.isSet(other)) {
        std::cerr << "ambler-gs: --" << rule.option << " " << rule.why << ": it takes no --"
                  << other << std::endl;
        return false;
      }
  }
  return true;
}

// ambler-gs's command line; nothing, after saying which value is wrong,
// when one is out of range or options do not combine.
std::optional<LaunchOptions> parseLaunchOptions(const QApplication& app) {
  QCommandLineParser parser;
  parser.setApplicationDescription("Ambler ground station (built-in simulator by default)");
  parser.addHelpOption();
  parser.addVersionOption();
  const QCommandLineOption seed_option(
      "seed",
      "Seed of the simulated ground: the obstacle course or the --family terrain (default 1).", "N",
      "1");
  const QCommandLineOption screenshot_option(
      "screenshot",
      "After the first scan is shown, save the window to FILE (PNG) and quit; after an error, "
      "save it and exit 1.",
      "FILE");
  const QCommandLineOption walk_option(
      "walk", "Start a walk of N steps at launch; --screenshot then waits for its first proposal.",
      "N");
  const QCommandLineOption replay_option(
      "replay", "Open the mission log FILE at launch; --screenshot then waits for it.", "FILE");
  const QCommandLineOption log_dir_option(
      "log-dir", "Folder for the mission logs of live walks.", "DIR",
      QStandardPaths::writableLocation(QStandardPaths::AppDataLocation) + "/missions");
  const QCommandLineOption startup_option(
      "startup-time",
      "Print as JSON the time from launch to the first rendered 3-D frame and to the first scan "
      "shown, and the 3-D view's frame time with the camera still and moving; quit (exit 1 "
      "after an error).");
  const QCommandLineOption responsiveness_option(
      "measure-responsiveness",
      "Run an auto-approved walk of 25 steps (or --walk N), a rock fit and the terrain mesh, "
      "measuring how late the GUI thread's event loop answers; print the stalls as JSON; quit "
      "(exit 1 after an error before the walk).");
  const QCommandLineOption soak_option(
      "soak",
      "A shift, accelerated: auto-approved walks on courses 1-10 in turn, each replayed and its "
      "tabs gone through, until N steps are walked; print resident memory and stalls as JSON; "
      "quit.",
      "N");
  const QCommandLineOption dtm_option(
      "dtm",
      "Simulate on a real terrain model (any DTM GDAL reads: GeoTIFF, PDS3/PDS4, ISIS3; projected "
      "CRS): a 60 m square around its centre (or --dtm-centre) at 10 cm.",
      "FILE");
  const QCommandLineOption family_option(
      "family",
      QString::fromStdString("Simulate on a terrain family drawn from the seed, as the "
                             "evaluations draw it (course, the obstacle course, by default): " +
                             ambler::sim::familyNamesListed() + "."),
      "NAME", "course");
  const QCommandLineOption dtm_centre_option(
      "dtm-centre",
      "EASTING,NORTHING of the rover's start in the DTM's CRS [m] (default: the raster's centre).",
      "E,N");
  parser.addOptions({dtm_option, dtm_centre_option, family_option, seed_option, screenshot_option,
                     walk_option, replay_option, log_dir_option, startup_option,
                     responsiveness_option, soak_option});
  parser.process(app);
  if (!optionsCombine(parser)) return std::nullopt;
  LaunchOptions o;
  bool seed_ok = false;
  o.seed = parser.value(seed_option).toULongLong(&seed_ok);
  if (!seed_ok || o.seed == 0 || o.seed > 999999) {
    std::cerr << "ambler-gs: --seed must be an integer from 1 to 999999" << std::endl;
    return std::nullopt;
  }
  if (parser.isSet(walk_option)) {
    o.walk_steps = parser.value(walk_option).toInt();
    if (o.walk_steps < 1 || o.walk_steps > 1000) {
      std::cerr << "ambler-gs: --walk must be an integer from 1 to 1000" << std::endl;
      return std::nullopt;
    }
  }
  if (parser.isSet(soak_option)) {
    o.soak_steps = parser.value(soak_option).toInt();
    if (o.soak_steps < 1 || o.soak_steps > 100000) {
      std::cerr << "ambler-gs: --soak must be an integer from 1 to 100000" << std::endl;
      return std::nullopt;
    }
  }
  o.log_dir = parser.value(log_dir_option);
  o.screenshot = parser.value(screenshot_option);
  o.replay = parser.value(replay_option);
  o.dtm = parser.value(dtm_option);
  const auto family = ambler::sim::parseFamily(parser.value(family_option).toStdString());
  if (!family) {
    std::cerr << "ambler-gs: --family must be " << ambler::sim::familyNamesListed() << std::endl;
    return std::nullopt;
  }
  o.family = *family;
  if (parser.isSet(dtm_centre_option)) {
    const QStringList parts = parser.value(dtm_centre_option).split(',');
    bool e_ok = false, n_ok = false;
    if (parts.size() == 2)
      o.dtm_centre = Eigen::Vector2d(parts[0].toDouble(&e_ok), parts[1].toDouble(&n_ok));
    if (!e_ok || !n_ok || !o.dtm_centre->allFinite()) {
      std::cerr << "ambler-gs: --dtm-centre must be EASTING,NORTHING in metres" << std::endl;
      return std::nullopt;
    }
    if (o.dtm.isEmpty()) {
      std::cerr << "ambler-gs: --dtm-centre needs --dtm" << std::endl;
      return std::nullopt;
    }
  }
  o.startup_time = parser.isSet(startup_option);
  o.responsiveness = parser.isSet(responsiveness_option);
  return o;
}

// The station's configuration from the installed files; nothing, after
// showing the operator why, when one cannot be read.
std::optional<ambler::gs::StationOptions> stationOptions(const LaunchOptions& launch) {
  ambler::gs::StationOptions options;
  options.seed = launch.seed;
  options.operator_id = qEnvironmentVariable("USER", "operator");
  options.log_dir = launch.log_dir;
  options.simulated_ground.family = launch.family;
  if (!launch.dtm.isEmpty())
    options.simulated_ground.dtm = ambler::sim::DtmSource{
        launch.dtm.toStdString(),
        {.centre = launch.dtm_centre, .width = 60.0, .height = 60.0, .resolution = 0.1}};
  try {
    options.scanner = ambler::sim::readScannerModel(ambler::findResource("config/scanner.json"));
    options.ground = ambler::gait::readInstalledGaitContext();
    options.simulator = ambler::rover::readInstalledSimulatedRoverConfig();
  } catch (const std::exception& e) {
    QMessageBox::critical(nullptr, "Ambler Ground Station", e.what());
    return std::nullopt;
  }
  return options;
}

// --startup-time: once the first scan is shown, prints the times from
// `since_start` to the first 3-D frame and to the scan, and the 3-D view's
// frame times, as JSON; quits (with 1 after an error instead).
void printStartupTimes(ambler::widgets::MainWindow& window, const QElapsedTimer& since_start) {
  auto first_frame = std::make_shared<qint64>(-1);
  QObject::connect(window.terrainView()->view(), &ambler::rendering::VtkView::frameRendered,
                   &window, [&since_start, first_frame] {
                     if (*first_frame < 0) *first_frame = since_start.elapsed();
                   });
  QObject::connect(&window, &ambler::widgets::MainWindow::scanShown, &window,
                   [&since_start, first_frame, &window] {
                     const qint64 scan_ms = since_start.elapsed();
                     auto* view = window.terrainView()->view();
                     // The 3-D view draws on its own thread: a frame drawn
                     // now holds the scan for sure (an upper bound).
                     view->renderedImage();
                     const qint64 scan_frame_ms = since_start.elapsed();
                     const auto still = frameTimes(view, false), moving = frameTimes(view, true);
                     std::cout << "{\"first_frame_ms\": " << *first_frame
                               << ", \"first_scan_shown_ms\": " << scan_ms
                               << ", \"first_scan_3d_frame_ms\": " << scan_frame_ms
                               << ", \"frame_ms_still\": " << still.first
                               << ", \"cells_still\": " << still.second
                               << ", \"frame_ms_moving\": " << moving.first
                               << ", \"cells_moving\": " << moving.second << "}" << std::endl;
                     QApplication::exit(0);
                   });
  QObject::connect(&window, &ambler::widgets::MainWindow::errorShown, &window,
                   [](const QString& message) {
                     printError(message);
                     QApplication::exit(1);
                   });
}

// --screenshot: the window once what the launch shows first is on screen
// (the replayed log, the walk's first proposal, or the first scan), or an
// error instead.
void screenshotWhenReady(ambler::gs::GroundStation& station, const LaunchOptions& launch) {
  auto& window = station.window();
  const QString path = launch.screenshot;
  if (!launch.replay.isEmpty())
    QObject::connect(&station, &ambler::gs::GroundStation::replayReady, &window,
                     [&window, path] { screenshotOnce(window, path); });
  else if (launch.walk_steps > 0)
    QObject::connect(&station, &ambler::gs::GroundStation::proposalShown, &window,
                     [&window, path] { screenshotOnce(window, path); });
  else
    QObject::connect(&window, &ambler::widgets::MainWindow::scanShown, &window,
                     [&window, path] { screenshotOnce(window, path); });
  // After an error, the window with the error in its status line, and exit 1.
  QObject::connect(&window, &ambler::widgets::MainWindow::errorShown, &window,
                   [&window, path](const QString& message) {
                     printError(message);
                     screenshotOnce(window, path, 1);
                   });
}

}  // namespace

int main(int argc, char** argv) {
  if (!haveADisplayOrNeedNone(argc, argv)) return 2;
  ambler::keepFreedMemoryForReuse();  // before the first scan's buffers
  // One heap for every thread. A heap per thread (the walk session, the
  // render threads, the pools, llvmpipe's) would keep each one's peak for
  // good; with two, or four, resident memory still climbs by steps over a
  // shift (README, A shift). The price: the threads share one heap's lock.
  mallopt(M_ARENA_MAX, 1);
  QElapsedTimer since_start;
  since_start.start();
  // VTK needs this format, and it must be the default before QApplication.
  QSurfaceFormat::setDefaultFormat(ambler::rendering::VtkView::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("Ambler");
  QApplication::setApplicationName("ambler-gs");
  QApplication::setApplicationVersion(AMBLER_VERSION);
  qRegisterMetaType<ambler::widgets::ScanDisplay>();

  const auto launch = parseLaunchOptions(app);
  if (!launch) return 2;
  const auto options = stationOptions(*launch);
  if (!options) return 1;
  ambler::gs::GroundStation station(*options);
  auto& window = station.window();
  // Always on: a stalled GUI thread is a defect an operator should be able
  // to report with figures (printed at exit).
  ambler::gs::EventLoopWatchdog watchdog;
  watchdog.start();
  if (launch->responsiveness)
    measureResponsiveness(station, watchdog, launch->walk_steps > 0 ? launch->walk_steps : 25);
  std::unique_ptr<ambler::gs::Soak> soak;
  if (launch->soak_steps > 0)
    soak = std::make_unique<ambler::gs::Soak>(station, watchdog, launch->soak_steps);
  if (launch->startup_time) printStartupTimes(window, since_start);
  if (!launch->screenshot.isEmpty()) screenshotWhenReady(station, *launch);

  window.show();
  // A replay shows the log alone: no simulated scan behind it.
  if (launch->replay.isEmpty())
    emit window.scanRequested(launch->seed);
  else
    station.openLog(launch->replay);
  const bool scripted = launch->responsiveness || soak;
  if (launch->walk_steps > 0 && !scripted) station.startWalk(launch->walk_steps);
  const int status = app.exec();
  if (!scripted) {
    std::cerr << "ambler-gs: event loop {";
    printStalls(watchdog.summary(), std::cerr);
    std::cerr << "}" << std::endl;
  }
  return status;
}
