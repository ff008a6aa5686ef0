// ambler-gs: the operator's ground station. Starts against the built-in
// simulator, so a new user sees a scan and its terrain on first launch.
#include <QApplication>
#include <QCommandLineParser>
#include <QMessageBox>
#include <QSurfaceFormat>
#include <QTimer>
#include <iostream>

#include "app/gs/SimulatorSource.h"
#include "core/Resources.h"
#include "rendering/VtkView.h"
#include "widgets/MainWindow.h"

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
  parser.addOptions({seed_option, screenshot_option});
  parser.process(app);
  bool seed_ok = false;
  const quint64 seed = parser.value(seed_option).toULongLong(&seed_ok);
  if (!seed_ok || seed == 0 || seed > 999999) {
    std::cerr << "ambler-gs: --seed must be an integer from 1 to 999999" << std::endl;
    return 2;
  }

  ambler::sim::ScannerModel model;
  try {
    model = ambler::sim::readScannerModel(ambler::findResource("config/scanner.json"));
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

  if (parser.isSet(screenshot_option)) {
    const QString path = parser.value(screenshot_option);
    QObject::connect(&simulator, &ambler::gs::SimulatorSource::scanReady, &app, [&, path] {
      QTimer::singleShot(800, &app, [&, path] {
        const bool saved = window.grab().save(path);
        std::cout << (saved ? "saved " : "could not save ") << path.toStdString() << std::endl;
        app.exit(saved ? 0 : 1);
      });
    });
  }

  window.setSeed(seed);
  window.show();
  emit window.scanRequested(seed);
  return app.exec();
}
