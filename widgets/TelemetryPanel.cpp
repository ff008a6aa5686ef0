#include "widgets/TelemetryPanel.h"

#include <QAreaSeries>
#include <QCategoryAxis>
#include <QChart>
#include <QChartView>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLineSeries>
#include <QTabWidget>
#include <QTableWidget>
#include <QVBoxLayout>
#include <QValueAxis>
#include <algorithm>
#include <array>
#include <cmath>

namespace ambler::widgets {

namespace {

// A value that rounds to zero prints as 0: "-0.000" shows a sign that
// says nothing about the rover.
QString fixed(double value, int decimals) {
  QString text = QString::number(value, 'f', decimals);
  if (text.startsWith('-') && text.mid(1).toDouble() == 0.0) text.remove(0, 1);
  return text;
}

// The TCA modules of cmu-1990 fig. 7 and the tasks each one does.
struct Lane {
  const char* name;
  QColor color;
  bool (*owns)(const executive::Task&);
};
const std::array<Lane, 4> kLanes = {{
    {"Perception", QColor(33, 150, 243), [](const executive::Task& t) { return t.name == "scan"; }},
    {"Planning", QColor(76, 175, 80), [](const executive::Task& t) { return t.name == "plan"; }},
    {"Operator", QColor(255, 152, 0),
     [](const executive::Task& t) { return t.kind == executive::TaskKind::kApproval; }},
    {"Control", QColor(156, 39, 176),
     [](const executive::Task& t) { return t.kind == executive::TaskKind::kCommand; }},
}};

QChartView* makeChartView(const QString& title) {
  auto* chart = new QChart;
  chart->setTitle(title);
  chart->legend()->setAlignment(Qt::AlignBottom);
  chart->setMargins(QMargins(4, 4, 4, 4));
  auto* view = new QChartView(chart);
  view->setRenderHint(QPainter::Antialiasing);
  view->setMinimumHeight(200);
  return view;
}

// The chart's axes are made once: rebuilding them at each refresh leaves
// stale tick labels on screen, or none at all.
void addAxes(QChart* chart, QAbstractAxis* y) {
  auto* x = new QValueAxis;
  x->setTitleText(QObject::tr("Time since start [s]"));
  // Fifths of the range (1, 2 or 5 times a power of ten, roundUp()): ticks
  // at 0.2, 0.4, 1 or 2 times a power of ten, which the labels' decimals
  // show exactly (quarters of 1 s read 0.3 and 0.8).
  x->setTickCount(6);
  chart->addAxis(x, Qt::AlignBottom);
  chart->addAxis(y, Qt::AlignLeft);
}

QValueAxis* valueAxis(const QString& title) {
  auto* axis = new QValueAxis;
  axis->setTitleText(title);
  return axis;
}

// The least of 1, 2 or 5 times a power of ten that is at least `v` (> 0).
double roundUp(double v) {
  const double decade = std::pow(10.0, std::floor(std::log10(v)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * decade >= v) return m * decade;
  return 10.0 * decade;
}

// A line series on the chart's two axes, named `name` (in the legend).
QLineSeries* addLine(QChart* chart, const QString& name) {
  auto* series = new QLineSeries;
  series->setName(name);
  chart->addSeries(series);
  series->attachAxis(chart->axes(Qt::Horizontal).front());
  series->attachAxis(chart->axes(Qt::Vertical).front());
  return series;
}

// Each leg's `value(sample, leg)` over time, and their range padded by `pad`.
template <typename Value>
void perLeg(const std::vector<executive::RoverSample>& history, double t0, double pad, Value value,
            std::vector<QList<QPointF>>& lines, double& lo, double& hi) {
  lines.assign(std::size_t(gait::kLegCount), {});
  lo = INFINITY, hi = -INFINITY;
  for (int leg = 0; leg < gait::kLegCount; ++leg) {
    auto& line = lines[std::size_t(leg)];
    line.reserve(qsizetype(history.size()));
    for (const auto& sample : history) {
      const double v = value(sample, leg);
      line.append({sample.time_s - t0, v});
      lo = std::min(lo, v), hi = std::max(hi, v);
    }
  }
  if (hi >= lo) lo -= pad, hi += pad;
}

}  // namespace

TelemetryPanel::TelemetryPanel(QWidget* parent)
    : QWidget(parent),
      pose_(new QLabel),
      legs_(new QTableWidget(gait::kLegCount, 6)),
      views_{makeChartView(tr("Module timing (cmu-1990 fig. 7)")),
             makeChartView(tr("Foot heights")), makeChartView(tr("Foot loads (force sensors)"))},
      plots_(new QTabWidget) {
  pose_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  pose_->setWordWrap(true);  // a longer line (a move under way) must not widen the panel
  legs_->setHorizontalHeaderLabels({tr("Leg"), tr("Contact"), tr("Load [kN]"), tr("Foot x [m]"),
                                    tr("Foot y [m]"), tr("Foot z [m]")});
  legs_->verticalHeader()->hide();
  legs_->horizontalHeader()->setSectionResizeMode(QHeaderView::Stretch);
  // Wide enough for every header, since the wrapped pose line above no
  // longer holds the column open.
  int header_width = 2 * legs_->frameWidth();
  for (int c = 0; c < legs_->columnCount(); ++c)
    header_width += legs_->horizontalHeader()->sectionSizeHint(c);
  legs_->setMinimumWidth(header_width);
  legs_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  legs_->verticalHeader()->setDefaultSectionSize(22);
  legs_->setFixedHeight(legs_->horizontalHeader()->sizeHint().height() + gait::kLegCount * 22 +
                        2 * legs_->frameWidth());
  auto* lanes = new QCategoryAxis;
  lanes->setRange(-0.5, double(kLanes.size()) - 0.5);
  lanes->setLabelsPosition(QCategoryAxis::AxisLabelsPositionOnValue);
  // Categories must be appended bottom up; the first lane is on top.
  for (std::size_t lane = kLanes.size(); lane-- > 0;)
    lanes->append(kLanes[lane].name, double(kLanes.size() - 1 - lane));
  addAxes(views_[kTiming]->chart(), lanes);
  addAxes(views_[kFeet]->chart(), valueAxis(tr("Foot z [m]")));
  addAxes(views_[kLoads]->chart(), valueAxis(tr("Load [kN]")));
  // A chart's size hint grows with its legend and tick labels as data
  // comes; taken into account, it would push the dock, and every view
  // above it, while the operator works.
  plots_->setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Ignored);
  plots_->setMinimumHeight(240);
  plots_->addTab(views_[kTiming], tr("Module timing"));
  plots_->addTab(views_[kFeet], tr("Foot heights"));
  plots_->addTab(views_[kLoads], tr("Foot loads"));
  for (std::size_t lane = 0; lane < kLanes.size(); ++lane) {
    auto* area = new QAreaSeries;
    auto* upper = new QLineSeries(area);
    auto* lower = new QLineSeries(area);
    area->setUpperSeries(upper);
    area->setLowerSeries(lower);
    area->setName(kLanes[lane].name);
    area->setColor(kLanes[lane].color);
    area->setBorderColor(kLanes[lane].color);
    QChart* chart = views_[kTiming]->chart();
    chart->addSeries(area);
    area->attachAxis(chart->axes(Qt::Horizontal).front());
    area->attachAxis(chart->axes(Qt::Vertical).front());
    series_[kTiming].push_back(upper);
    series_[kTiming].push_back(lower);
  }
  views_[kTiming]->chart()->legend()->hide();
  // One colour per leg on both plots (the chart's theme has five).
  static const std::array<QColor, gait::kLegCount> kLegColours = {
      QColor(31, 119, 180), QColor(255, 127, 14),  QColor(44, 160, 44),
      QColor(214, 39, 40),  QColor(148, 103, 189), QColor(140, 86, 75)};
  for (Plot plot : {kFeet, kLoads})
    for (int leg = 0; leg < gait::kLegCount; ++leg) {
      auto* line = addLine(views_[plot]->chart(), tr("leg %1").arg(leg));
      line->setPen(QPen(kLegColours[std::size_t(leg)], 2.0));
      series_[plot].push_back(line);
    }
  for (int plot = 0; plot < kPlotCount; ++plot) {
    cursors_[plot] = addLine(views_[plot]->chart(), tr("now"));
    cursors_[plot]->setPen(QPen(Qt::red, 1.5, Qt::DashLine));
    cursors_[plot]->setVisible(false);
  }
  connect(plots_, &QTabWidget::currentChanged, this, [this] { redrawVisible(); });
  // Wide and short, to sit under the views: the state on the left, the
  // plots over time on the right.
  auto* state = new QVBoxLayout;
  state->addWidget(pose_);
  state->addWidget(legs_);
  state->addStretch(1);
  auto* layout = new QHBoxLayout(this);
  layout->addLayout(state, 2);
  layout->addWidget(plots_, 3);
  setRover(std::nullopt);
}

void TelemetryPanel::setRover(const std::optional<executive::RoverSample>& rover) {
  if (!rover) {
    pose_->setText(tr("No rover state yet"));
    for (int r = 0; r < gait::kLegCount; ++r)
      for (int c = 0; c < legs_->columnCount(); ++c)
        legs_->setItem(r, c, new QTableWidgetItem(c == 0 ? QString::number(r) : "–"));
    return;
  }
  const auto& stance = rover->stance;
  const auto& b = stance.body;
  const QString pose = tr("Body x %1 m, y %2 m, link plane z %3 m, heading %4°")
                           .arg(fixed(b.xy.x(), 3), fixed(b.xy.y(), 3), fixed(b.link_z, 3),
                                fixed(b.heading_rad * 180.0 / M_PI, 1));
  pose_->setText(rover->moving ? tr("%1 · moving: where the move under way began").arg(pose)
                               : pose);
  for (int r = 0; r < gait::kLegCount; ++r) {
    const auto& f = stance.feet[std::size_t(r)];
    const bool contact = stance.supporting[std::size_t(r)];
    const QStringList cells = {QString::number(r),
                               contact ? tr("yes") : tr("no"),
                               QString::number(rover->force_n[std::size_t(r)] / 1000.0, 'f', 2),
                               fixed(f.x(), 3),
                               fixed(f.y(), 3),
                               fixed(f.z(), 3)};
    for (int c = 0; c < cells.size(); ++c) {
      auto* item = new QTableWidgetItem(cells[c]);
      if (c == 1 && !contact) item->setForeground(QColor(183, 28, 28));
      legs_->setItem(r, c, item);
    }
  }
}

// Each lane is an area between its baseline and a step line that rises
// while one of its tasks runs.
void TelemetryPanel::setModuleTiming(const std::vector<executive::Task>& tasks, double t0,
                                     double now_s) {
  auto& data = data_[kTiming];
  data.lines.assign(2 * kLanes.size(), {});
  for (std::size_t lane = 0; lane < kLanes.size(); ++lane) {
    const double base = double(kLanes.size() - 1 - lane);
    auto& upper = data.lines[2 * lane];
    upper.append({0, base - 0.3});
    for (const auto& t : tasks) {
      if (!kLanes[lane].owns(t) || t.started_s <= 0) continue;
      const double a = t.started_s - t0;
      const double b = (t.ended_s > 0 ? t.ended_s : now_s) - t0;
      upper.append({{a, base - 0.3}, {a, base + 0.3}, {b, base + 0.3}, {b, base - 0.3}});
    }
    upper.append({now_s - t0, base - 0.3});
    data.lines[2 * lane + 1] = {{0, base - 0.3}, {now_s - t0, base - 0.3}};
  }
  data.span_s = now_s - t0;
  data.y_lo = -0.5, data.y_hi = double(kLanes.size()) - 0.5;
  data.stale = true;
  redrawVisible();
}

void TelemetryPanel::setHistory(const std::vector<executive::RoverSample>& history, double t0) {
  const double span = history.empty() ? 1.0 : history.back().time_s - t0;
  auto& feet = data_[kFeet];
  perLeg(
      history, t0, 0.05, [](const auto& s, int leg) { return s.stance.feet[std::size_t(leg)].z(); },
      feet.lines, feet.y_lo, feet.y_hi);
  auto& loads = data_[kLoads];
  perLeg(
      history, t0, 1.0, [](const auto& s, int leg) { return s.force_n[std::size_t(leg)] / 1000.0; },
      loads.lines, loads.y_lo, loads.y_hi);
  feet.span_s = loads.span_s = span;
  feet.stale = loads.stale = true;
  redrawVisible();
}

void TelemetryPanel::redrawVisible() {
  for (int plot = 0; plot < kPlotCount; ++plot)
    if (plots_->currentWidget() == views_[plot] && data_[plot].stale) redraw(Plot(plot));
}

void TelemetryPanel::redraw(Plot plot) {
  auto& data = data_[plot];
  data.stale = false;
  QChart* chart = views_[plot]->chart();
  auto* x = qobject_cast<QValueAxis*>(chart->axes(Qt::Horizontal).front());
  // The axis is laid out again (its labels measured) whenever its range
  // changes: it grows by round steps, not with every refresh.
  const double end = roundUp(std::max(data.span_s, 1.0));
  const QString format = end < 10 ? "%.1f" : "%.0f";
  if (x->max() != end) x->setRange(0, end);
  if (x->labelFormat() != format) x->setLabelFormat(format);
  // The lanes' axis is a category axis, set once.
  auto* y = qobject_cast<QValueAxis*>(chart->axes(Qt::Vertical).front());
  if (plot != kTiming && y && data.y_hi > data.y_lo) y->setRange(data.y_lo, data.y_hi);
  for (std::size_t i = 0; i < series_[plot].size(); ++i)
    series_[plot][i]->replace(i < data.lines.size() ? data.lines[i] : QList<QPointF>{});
  auto* cursor = cursors_[plot];
  cursor->setVisible(data.cursor_s.has_value());
  if (data.cursor_s) cursor->replace({{*data.cursor_s, data.y_lo}, {*data.cursor_s, data.y_hi}});
}

void TelemetryPanel::setCursor(std::optional<double> time_s) {
  for (auto& data : data_) {
    data.cursor_s = time_s;
    data.stale = true;
  }
  redrawVisible();
}

}  // namespace ambler::widgets
