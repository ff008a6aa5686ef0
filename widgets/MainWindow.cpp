#include "widgets/MainWindow.h"

#include <QAction>
#include <QChartView>
#include <QCloseEvent>
#include <QDir>
#include <QDockWidget>
#include <QFile>
#include <QFileDialog>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QProgressBar>
#include <QScreen>
#include <QSettings>
#include <QSpinBox>
#include <QSplitter>
#include <QStatusBar>
#include <QTabWidget>
#include <QToolBar>
#include <utility>

#include "terrain/ElevationMapFile.h"
#include "widgets/CommandLogView.h"
#include "widgets/DangerPanel.h"
#include "widgets/ElidedLabel.h"
#include "widgets/MapView.h"
#include "widgets/RangeImageView.h"
#include "widgets/SamplingPanel.h"
#include "widgets/StepApprovalPanel.h"
#include "widgets/TelemetryPanel.h"
#include "widgets/TerrainMeshPanel.h"
#include "widgets/TerrainView.h"
#include "widgets/TimelineBar.h"

namespace ambler::widgets {

MainWindow::MainWindow(QWidget* parent)
    : QMainWindow(parent),
      range_view_(new RangeImageView),
      terrain_view_(new TerrainView),
      seed_box_(new QSpinBox),
      scan_action_(new QAction(tr("Take scan"), this)),
      walk_command_(new WalkCommandBar),
      walk_action_(new QAction(tr("Walk"), this)),
      hold_action_(new QAction(tr("HOLD"), this)),
      approval_(new StepApprovalPanel),
      map_view_(new MapView),
      sampling_(new SamplingPanel),
      mesh_panel_(new TerrainMeshPanel),
      danger_panel_(new DangerPanel),
      views_(new QTabWidget),
      status_(new ElidedLabel),
      link_status_(new QLabel),
      progress_(new QProgressBar),
      telemetry_(new TelemetryPanel),
      command_log_(new CommandLogView),
      timeline_(new TimelineBar) {
  setWindowTitle(tr("Ambler Ground Station"));
  auto* splitter = new QSplitter(Qt::Horizontal);
  views_->addTab(range_view_, tr("Range image"));
  views_->addTab(map_view_, tr("Terrain map"));
  views_->addTab(sampling_, tr("Rock sampling"));
  views_->addTab(mesh_panel_, tr("Terrain mesh"));
  views_->addTab(danger_panel_, tr("Danger map"));
  splitter->addWidget(views_);
  splitter->addWidget(terrain_view_);
  splitter->setStretchFactor(0, 3);
  splitter->setStretchFactor(1, 3);
  setCentralWidget(splitter);

  auto* toolbar = addToolBar(tr("Scan"));
  toolbar->setObjectName("scan-toolbar");
  toolbar->addWidget(new QLabel(tr("Terrain seed: ")));
  seed_box_->setRange(1, 999999);
  seed_box_->setToolTip(tr("Seed of the simulated ground (the obstacle course or --family)"));
  toolbar->addWidget(seed_box_);
  scan_action_->setShortcut(Qt::Key_F5);
  scan_action_->setToolTip(tr("Acquire a new range image (F5)"));
  toolbar->addAction(scan_action_);
  connect(scan_action_, &QAction::triggered, this, [this] { emit scanRequested(seed()); });
  toolbar->addSeparator();
  toolbar->addWidget(walk_command_);
  walk_action_->setToolTip(
      tr("Walk the rover these steps along this path; each waits for your "
         "approval unless auto-approve is on"));
  toolbar->addAction(walk_action_);
  connect(walk_action_, &QAction::triggered, this,
          [this] { emit walkRequested(walk_command_->command()); });
  // Red, at the operator's hand on the toolbar and on Esc: a signed Hold
  // stops the rover whatever the walk is doing.
  hold_action_->setShortcut(Qt::Key_Escape);
  hold_action_->setToolTip(
      tr("Stop the rover now: a signed Hold; it stays still until the next walk (Esc)"));
  toolbar->addSeparator();
  toolbar->addAction(hold_action_);
  toolbar->widgetForAction(hold_action_)
      ->setStyleSheet(
          "QToolButton { color: white; background: #b71c1c; font-weight: bold; "
          "padding: 2px 14px; } "
          "QToolButton:disabled { color: #e0e0e0; background: #9e9e9e; }");
  connect(hold_action_, &QAction::triggered, this, &MainWindow::holdRequested);

  // The approval dock keeps the window's whole height: Approve and Reject
  // stay in view on a 768-pixel screen with the telemetry open.
  setCorner(Qt::BottomRightCorner, Qt::RightDockWidgetArea);
  addDock(tr("Step approval"), "step-approval-dock", approval_, Qt::RightDockWidgetArea);
  auto* telemetry =
      addDock(tr("Telemetry"), "telemetry-dock", telemetry_, Qt::BottomDockWidgetArea);
  auto* events = addDock(tr("Events and commands"), "command-log-dock", command_log_,
                         Qt::BottomDockWidgetArea);
  tabifyDockWidget(telemetry, events);
  telemetry->raise();
  // The timeline spans the window's width, under everything else.
  timeline_bar_ = new QToolBar(tr("Replay timeline"), this);
  timeline_bar_->setObjectName("timeline-toolbar");
  timeline_bar_->setMovable(false);
  timeline_bar_->addWidget(timeline_);
  addToolBar(Qt::BottomToolBarArea, timeline_bar_);
  timeline_bar_->hide();
  addMenus();

  progress_->setRange(0, 0);  // busy indicator unless the work has a fraction to show
  progress_->setMaximumWidth(140);
  progress_->hide();
  // The link's figures stay whole; a long message yields (its tooltip has
  // it all).
  status_->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Preferred);
  statusBar()->addWidget(status_, 1);
  statusBar()->addPermanentWidget(link_status_);
  statusBar()->addPermanentWidget(progress_);
  // A readout stands in for the status while the pointer is over a view.
  auto readout = [this](const QString& text) {
    status_->setText(text.isEmpty() ? status_text_ : text);
  };
  connect(range_view_, &RangeImageView::readoutChanged, this, readout);
  connect(map_view_, &MapView::readoutChanged, this, readout);

  default_state_ = saveState();
  QSettings settings;
  restoreState(settings.value("main/state").toByteArray());
  saved_geometry_ = settings.value("main/geometry").toByteArray();
  timeline_bar_->hide();  // until a log is opened, whatever was saved
}

void MainWindow::showEvent(QShowEvent* e) {
  QMainWindow::showEvent(e);
  if (std::exchange(placed_, true)) return;
  // Where the operator left it, unless that does not fit this screen (a
  // layout saved on a larger monitor).
  if (!restoreGeometry(saved_geometry_) || !screen()->availableGeometry().contains(frameGeometry()))
    fitToScreen();
}

void MainWindow::fitToScreen() {
  const QRect available = screen()->availableGeometry();
  const QSize preferred(1600, 1000);
  // The frame (title bar, borders) comes on top of the size given.
  const QSize frame = frameGeometry().size() - geometry().size();
  const QSize size = preferred.boundedTo(available.size() - frame);
  resize(size);
  move(available.topLeft() + QPoint((available.width() - size.width() - frame.width()) / 2,
                                    (available.height() - size.height() - frame.height()) / 2));
}

void MainWindow::resetLayout() {
  restoreState(default_state_);
  timeline_bar_->setVisible(replaying_);
  fitToScreen();
}

QDockWidget* MainWindow::addDock(const QString& title, const QString& name, QWidget* widget,
                                 Qt::DockWidgetArea area) {
  auto* dock = new QDockWidget(title, this);
  dock->setObjectName(name);  // for saveState/restoreState
  dock->setWidget(widget);
  addDockWidget(area, dock);
  return dock;
}

void MainWindow::addMenus() {
  auto* file = menuBar()->addMenu(tr("&File"));
  auto* connect_action = file->addAction(tr("&Connect…"), this, &MainWindow::connectRequested);
  connect_action->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_K));
  connect_action->setToolTip(tr("Built-in simulator, ambler-sim or a rover over DDS, or a log"));
  auto* open = file->addAction(tr("&Open mission log…"), this, [this] {
    const QString path = QFileDialog::getOpenFileName(this, tr("Open mission log"), {},
                                                      tr("Mission logs (*.sqlite);;All files (*)"));
    if (!path.isEmpty()) emit openLogRequested(path);
  });
  open->setShortcut(QKeySequence::Open);
  file->addSeparator();
  auto report = [this](const Refusal& written, const QString& done) {
    if (written.refused())
      showError(QString::fromStdString(written.why()));
    else
      setStatus(done);
  };
  file->addAction(tr("Export map layers (TIFF)…"), this, [this, report] {
    const QString dir = QFileDialog::getExistingDirectory(this, tr("Folder for the map layers"));
    if (!dir.isEmpty()) report(exportMapLayers(dir), tr("Map layers written to %1").arg(dir));
  });
  file->addAction(tr("Export plots (PNG)…"), this, [this, report] {
    const QString dir = QFileDialog::getExistingDirectory(this, tr("Folder for the plots"));
    if (!dir.isEmpty()) report(exportPlots(dir), tr("Plots written to %1").arg(dir));
  });
  file->addAction(tr("Export events and commands (CSV)…"), this, [this, report] {
    const QString path = QFileDialog::getSaveFileName(this, tr("Events and commands"),
                                                      "commands.csv", tr("CSV (*.csv)"));
    if (!path.isEmpty()) report(exportTable(path), tr("Table written to %1").arg(path));
  });
  file->addSeparator();
  file->addAction(tr("&Quit"), QKeySequence::Quit, this, &QWidget::close);
  auto* rover = menuBar()->addMenu(tr("&Rover"));
  request_authority_ =
      rover->addAction(tr("&Request command authority"), this, &MainWindow::authorityRequested);
  request_authority_->setToolTip(
      tr("Ask the console in command to hand it over; granted at once when none holds it"));
  hand_over_ =
      rover->addAction(tr("&Hand over command authority"), this, &MainWindow::handOverRequested);
  hand_over_->setEnabled(false);
  auto* view = menuBar()->addMenu(tr("&View"));
  for (auto* dock : findChildren<QDockWidget*>()) view->addAction(dock->toggleViewAction());
  view->addSeparator();
  view->addAction(tr("&Reset layout"), this, &MainWindow::resetLayout)
      ->setToolTip(tr("Every dock back in its place, the window fitted to this screen"));
}

void MainWindow::setReplay(const QString& what) {
  setWindowTitle(what.isEmpty() ? tr("Ambler Ground Station")
                                : tr("Ambler Ground Station — replay of %1").arg(what));
  replaying_ = !what.isEmpty();
  timeline_bar_->setVisible(replaying_);
  approval_->setEnabled(what.isEmpty());
  approval_->setReplay(replaying_);
  map_view_->setFootholdEditable(!replaying_);
  walk_action_->setEnabled(what.isEmpty());
  walk_command_->setEnabled(what.isEmpty());
  hold_action_->setEnabled(what.isEmpty());
  scan_action_->setEnabled(what.isEmpty());
  seed_box_->setEnabled(what.isEmpty());
  if (!what.isEmpty()) showMapView();
}

namespace {

Refusal refused(const QString& why) { return Refusal::because(why.toStdString()); }

}  // namespace

Refusal MainWindow::exportMapLayers(const QString& dir) const {
  const auto& map = map_view_->map();
  if (!map) return refused(tr("There is no terrain map to export yet."));
  try {
    terrain::writeElevationMap(*map, dir.toStdString());
  } catch (const std::exception& e) {
    return refused(tr("Could not write the map layers: %1").arg(e.what()));
  }
  return {};
}

Refusal MainWindow::exportPlots(const QString& dir) const {
  const std::pair<QChartView*, QString> plots[] = {{telemetry_->timingView(), "module-timing.png"},
                                                   {telemetry_->feetView(), "foot-heights.png"},
                                                   {telemetry_->loadsView(), "foot-loads.png"}};
  for (const auto& [view, name] : plots) {
    const QString path = QDir(dir).filePath(name);
    if (!view->grab().save(path)) return refused(tr("Could not write %1").arg(path));
  }
  return {};
}

Refusal MainWindow::exportTable(const QString& path) const {
  QFile file(path);
  if (!file.open(QIODevice::WriteOnly | QIODevice::Truncate | QIODevice::Text) ||
      file.write(command_log_->toCsv().toUtf8()) < 0)
    return refused(tr("Could not write %1: %2").arg(path, file.errorString()));
  return {};
}

quint64 MainWindow::seed() const { return quint64(seed_box_->value()); }

void MainWindow::setSeed(quint64 seed) { seed_box_->setValue(int(seed)); }

void MainWindow::showScan(const ScanDisplay& display) {
  range_view_->setImage(display.scan);
  terrain_view_->setScene(display);
  const auto t = display.scan.sensor_to_world.translation();
  setStatus(tr("Scan %1 x %2, %3 returns, sensor at (%4, %5, %6) m, simulated in %7 ms")
                .arg(display.scan.rows())
                .arg(display.scan.cols())
                .arg(display.scan.returnCount())
                .arg(t.x(), 0, 'f', 2)
                .arg(t.y(), 0, 'f', 2)
                .arg(t.z(), 0, 'f', 2)
                .arg(display.scan_ms, 0, 'f', 0));
  emit scanShown();
}

void MainWindow::showMapView() { views_->setCurrentWidget(map_view_); }

void MainWindow::showSamplingView() { views_->setCurrentWidget(sampling_); }

void MainWindow::showMeshView() { views_->setCurrentWidget(mesh_panel_); }

void MainWindow::showDangerView() { views_->setCurrentWidget(danger_panel_); }

void MainWindow::setLinkStatus(const QString& text, bool stale) {
  link_status_->setText(text);
  link_status_->setStyleSheet(stale ? "color:#b71c1c;font-weight:bold" : "");
}

void MainWindow::setAuthority(bool this_console_holds, const QString& asking) {
  request_authority_->setEnabled(!this_console_holds && !replaying_);
  hand_over_->setEnabled(this_console_holds && !asking.isEmpty() && !replaying_);
  hand_over_->setText(asking.isEmpty() ? tr("&Hand over command authority")
                                       : tr("&Hand over command authority to %1").arg(asking));
}

void MainWindow::showError(const QString& message) {
  setStatus(tr("Error: %1").arg(message));
  emit errorShown(message);
  QMessageBox::warning(this, tr("Ambler Ground Station"), message);
}

void MainWindow::setBusy(const QString& what) {
  progress_->setVisible(!what.isEmpty());
  scan_action_->setEnabled(what.isEmpty() && !replaying_);
  if (!what.isEmpty()) setStatus(what);
}

void MainWindow::setStatus(const QString& text) {
  status_text_ = text;
  status_->setText(text);
  status_->setToolTip(text);
}

void MainWindow::closeEvent(QCloseEvent* e) {
  QSettings settings;
  settings.setValue("main/geometry", saveGeometry());
  settings.setValue("main/state", saveState());
  e->accept();
}

}  // namespace ambler::widgets
