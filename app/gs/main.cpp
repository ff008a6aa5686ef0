// ambler-gs: the operator's ground station. Starts against the built-in
// simulator, so a new user sees a scan and its terrain on first launch.
#include <QApplication>
#include <QCommandLineParser>
#include <QMessageBox>
#include <QStatusBar>
#include <QSurfaceFormat>
#include <QTimer>
#include <iostream>

#include "app/gs/SimulatorSource.h"
#include "app/gs/WalkSession.h"
#include "core/Resources.h"
#include "rendering/VtkView.h"
#include "widgets/MainWindow.h"
#include "widgets/MapView.h"
#include "widgets/StepApprovalPanel.h"

int main(int argc, char** argv) {
  // VTK needs this format, and it must be the default before QApplication.
  QSurfaceFormat::setDefaultFormat(ambler::rendering::VtkView::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("Ambler");
  QApplication::setApplicationName("ambler-gs");
  QApplication::setApplicationVersion(AMBLER_VERSION);
  qRegisterMetaType<ambler::widgets::ScanDisplay>();

  QCommandLineParser parser;
  parser.setApplicationDescription("Ambler ground station (built-in simulator)");
  parser.addHelpOption();
  parser.addVersionOption();
  const QCommandLineOption seed_option("seed", "Seed of the simulated obstacle course.", "N", "1");
  const QCommandLineOption screenshot_option(
      "screenshot", "After the first scan is shown, save the window to FILE (PNG) and quit.",
      "FILE");
  const QCommandLineOption walk_option(
      "walk", "Start a walk of N steps at launch; --screenshot then waits for its first proposal.",
      "N");
  parser.addOptions({seed_option, screenshot_option, walk_option});
  parser.process(app);
  bool seed_ok = false;
  const quint64 seed = parser.value(seed_option).toULongLong(&seed_ok);
  if (!seed_ok || seed == 0 || seed > 999999) {
    std::cerr << "ambler-gs: --seed must be an integer from 1 to 999999" << std::endl;
    return 2;
  }

  ambler::sim::ScannerModel model;
  ambler::walk::WalkConfig walk_config;
  try {
    model = ambler::sim::readScannerModel(ambler::findResource("config/scanner.json"));
    walk_config = ambler::walk::readDefaultWalkConfig();
  } catch (const std::exception& e) {
    QMessageBox::critical(nullptr, "Ambler Ground Station", e.what());
    return 1;
  }

  ambler::widgets::MainWindow window;
  ambler::gs::SimulatorSource simulator(model);
  QObject::connect(&window, &ambler::widgets::MainWindow::scanRequested, &simulator,
                   [&](quint64 s) {
                     window.setBusy(QObject::tr("Scanning the simulated course (seed %1)…").arg(s));
                     simulator.requestScan(s);
                   });
  QObject::connect(&simulator, &ambler::gs::SimulatorSource::scanReady, &window,
                   [&](const ambler::widgets::ScanDisplay& d) {
                     window.setBusy({});
                     window.showScan(d);
                   });
  QObject::connect(&simulator, &ambler::gs::SimulatorSource::scanFailed, &window,
                   [&](const QString& message) {
                     window.setBusy({});
                     window.showError(message);
                   });

  // The walk: the executive over the simulator in this process, its
  // proposals in the approval panel, the link's age in the status bar.
  const QString operator_id = qEnvironmentVariable("USER", "operator");
  ambler::gs::WalkSession session(walk_config, seed, operator_id);
  auto* panel = window.approvalPanel();
  QObject::connect(&session, &ambler::gs::WalkSession::changed, panel, [&] {
    panel->setPhase(QString::fromStdString(phaseName(session.executive().phase())));
    panel->showProposal(session.pending());
    window.mapView()->setMap(session.executive().map());
    window.mapView()->setProposal(session.pending());
  });
  QObject::connect(window.mapView(), &ambler::widgets::MapView::footholdClicked, &session,
                   [&](quint64 id, double x, double y) {
                     if (const auto why = session.editFoothold(id, x, y); !why.isEmpty())
                       window.statusBar()->showMessage(why, 5000);
                   });
  QObject::connect(panel, &ambler::widgets::StepApprovalPanel::approveRequested, &session,
                   [&](quint64 id) {
                     if (const auto why = session.approve(id); !why.isEmpty())
                       window.showError(why);
                   });
  QObject::connect(
      panel, &ambler::widgets::StepApprovalPanel::rejectRequested, &session,
      [&](quint64 id) { session.reject(id, QObject::tr("rejected by %1").arg(operator_id)); });
  QObject::connect(panel, &ambler::widgets::StepApprovalPanel::autoApproveChanged, &session,
                   &ambler::gs::WalkSession::setAutoApprove);
  QObject::connect(&window, &ambler::widgets::MainWindow::walkRequested, &session, [&] {
    window.showMapView();
    session.start(5);
  });
  QTimer link_timer;
  QObject::connect(&link_timer, &QTimer::timeout, &window, [&] {
    const auto age = session.linkAgeS();
    const bool stale = !age || *age > 3.0;
    window.setLinkStatus(age ? QObject::tr("%1: last data %2 s ago")
                                   .arg(session.linkDescription())
                                   .arg(*age, 0, 'f', 1)
                             : QObject::tr("%1: no data yet").arg(session.linkDescription()),
                         stale && session.executive().phase() != ambler::executive::Phase::kIdle);
  });
  link_timer.start(500);

  const int walk_steps = parser.isSet(walk_option) ? parser.value(walk_option).toInt() : 0;
  if (parser.isSet(walk_option) && (walk_steps < 1 || walk_steps > 1000)) {
    std::cerr << "ambler-gs: --walk must be an integer from 1 to 1000" << std::endl;
    return 2;
  }
  if (parser.isSet(screenshot_option)) {
    const QString path = parser.value(screenshot_option);
    auto shoot = [&, path] {
      QTimer::singleShot(800, &app, [&, path] {
        const bool saved = window.grab().save(path);
        std::cout << (saved ? "saved " : "could not save ") << path.toStdString() << std::endl;
        app.exit(saved ? 0 : 1);
      });
    };
    if (walk_steps > 0)
      QObject::connect(&session, &ambler::gs::WalkSession::changed, &app, [&, shoot] {
        static bool shot = false;
        if (session.pending() && !std::exchange(shot, true)) shoot();
      });
    else
      QObject::connect(&simulator, &ambler::gs::SimulatorSource::scanReady, &app, shoot);
  }

  window.setSeed(seed);
  window.show();
  emit window.scanRequested(seed);
  if (walk_steps > 0) {
    window.showMapView();
    session.start(walk_steps);
  }
  return app.exec();
}
