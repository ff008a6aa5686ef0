#include "widgets/MainWindow.h"

#include <QAction>
#include <QCloseEvent>
#include <QDockWidget>
#include <QLabel>
#include <QMessageBox>
#include <QProgressBar>
#include <QSettings>
#include <QSpinBox>
#include <QSplitter>
#include <QStatusBar>
#include <QTabWidget>
#include <QToolBar>

#include "widgets/MapView.h"
#include "widgets/RangeImageView.h"
#include "widgets/StepApprovalPanel.h"
#include "widgets/TerrainView.h"

namespace ambler::widgets {

MainWindow::MainWindow(QWidget* parent)
    : QMainWindow(parent),
      range_view_(new RangeImageView),
      terrain_view_(new TerrainView),
      seed_box_(new QSpinBox),
      scan_action_(new QAction(tr("Take scan"), this)),
      walk_action_(new QAction(tr("Walk 5 steps"), this)),
      approval_(new StepApprovalPanel),
      map_view_(new MapView),
      views_(new QTabWidget),
      status_(new QLabel),
      link_status_(new QLabel),
      progress_(new QProgressBar) {
  setWindowTitle(tr("Ambler Ground Station"));
  auto* splitter = new QSplitter(Qt::Horizontal);
  views_->addTab(range_view_, tr("Range image"));
  views_->addTab(map_view_, tr("Terrain map"));
  splitter->addWidget(views_);
  splitter->addWidget(terrain_view_);
  splitter->setStretchFactor(0, 3);
  splitter->setStretchFactor(1, 3);
  setCentralWidget(splitter);

  auto* toolbar = addToolBar(tr("Scan"));
  toolbar->setObjectName("scan-toolbar");
  toolbar->addWidget(new QLabel(tr("Terrain seed: ")));
  seed_box_->setRange(1, 999999);
  seed_box_->setToolTip(tr("Seed of the simulated obstacle course"));
  toolbar->addWidget(seed_box_);
  scan_action_->setShortcut(Qt::Key_F5);
  scan_action_->setToolTip(tr("Acquire a new range image (F5)"));
  toolbar->addAction(scan_action_);
  connect(scan_action_, &QAction::triggered, this, [this] { emit scanRequested(seed()); });
  walk_action_->setToolTip(
      tr("Walk the rover five steps; each waits for your approval unless auto-approve is on"));
  toolbar->addAction(walk_action_);
  connect(walk_action_, &QAction::triggered, this, &MainWindow::walkRequested);

  auto* dock = new QDockWidget(tr("Step approval"), this);
  dock->setObjectName("step-approval-dock");  // for saveState/restoreState
  dock->setWidget(approval_);
  addDockWidget(Qt::RightDockWidgetArea, dock);

  progress_->setRange(0, 0);  // busy indicator: scans have no fraction to show
  progress_->setMaximumWidth(140);
  progress_->hide();
  statusBar()->addWidget(status_, 1);
  statusBar()->addPermanentWidget(link_status_);
  statusBar()->addPermanentWidget(progress_);
  auto readout = [this](const QString& text) {
    if (!text.isEmpty())
      statusBar()->showMessage(text);
    else
      statusBar()->clearMessage();
  };
  connect(range_view_, &RangeImageView::readoutChanged, this, readout);
  connect(map_view_, &MapView::readoutChanged, this, readout);

  QSettings settings;
  restoreGeometry(settings.value("main/geometry").toByteArray());
  restoreState(settings.value("main/state").toByteArray());
  if (!settings.contains("main/geometry")) resize(1280, 760);
}

quint64 MainWindow::seed() const { return quint64(seed_box_->value()); }

void MainWindow::setSeed(quint64 seed) { seed_box_->setValue(int(seed)); }

void MainWindow::showScan(const ScanDisplay& display) {
  range_view_->setImage(display.scan);
  terrain_view_->setScene(display);
  const auto t = display.scan.sensor_to_world.translation();
  status_->setText(tr("Scan %1 x %2, %3 returns, sensor at (%4, %5, %6) m, simulated in %7 ms")
                       .arg(display.scan.rows())
                       .arg(display.scan.cols())
                       .arg(display.scan.returnCount())
                       .arg(t.x(), 0, 'f', 2)
                       .arg(t.y(), 0, 'f', 2)
                       .arg(t.z(), 0, 'f', 2)
                       .arg(display.scan_ms, 0, 'f', 0));
}

void MainWindow::showMapView() { views_->setCurrentWidget(map_view_); }

void MainWindow::setLinkStatus(const QString& text, bool stale) {
  link_status_->setText(text);
  link_status_->setStyleSheet(stale ? "color:#b71c1c;font-weight:bold" : "");
}

void MainWindow::showError(const QString& message) {
  status_->setText(tr("Error: %1").arg(message));
  QMessageBox::warning(this, tr("Ambler Ground Station"), message);
}

void MainWindow::setBusy(const QString& what) {
  progress_->setVisible(!what.isEmpty());
  scan_action_->setEnabled(what.isEmpty());
  if (!what.isEmpty()) status_->setText(what);
}

void MainWindow::closeEvent(QCloseEvent* e) {
  QSettings settings;
  settings.setValue("main/geometry", saveGeometry());
  settings.setValue("main/state", saveState());
  e->accept();
}

}  // namespace ambler::widgets
