#include "widgets/MapView.h"

#include <QComboBox>
#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>
#include <algorithm>
#include <cmath>

#include "rendering/ColorMap.h"
#include "widgets/ColorBar.h"

namespace ambler::widgets {

namespace {

constexpr int kMargin = 8;
constexpr int kTop = 36;  // room for the layer switch
constexpr int kBarWidth = 18;
constexpr int kBarSpace = 110;
constexpr int kReadoutHeight = 18;
constexpr double kHalfViewM = 7.0;  // the view spans the rover's reach and more

const QColor kUnknownColor = toQColor(rendering::kNoDataColor);
const QColor kShadowColor(120, 40, 140);
const QColor kKnownColor(200, 200, 200);
const QColor kObliqueColor(215, 160, 60);
const QColor kCannotStandColor(150, 30, 30);

// Oblique cells show their value faded towards the no-data colour, dimmer:
// a height to see, not ground to stand on.
QColor faded(const QColor& c) {
  return QColor((c.red() + kUnknownColor.red()) / 2, (c.green() + kUnknownColor.green()) / 2,
                (c.blue() + kUnknownColor.blue()) / 2);
}

QString layerUnit(MapView::Shown shown) {
  switch (shown) {
    case MapView::Shown::kSigma:
      return QObject::tr("Sigma [m]");
    case MapView::Shown::kCriterion:
      return QObject::tr("Roughness cost [0–1]");
    case MapView::Shown::kComposite:
      return QObject::tr("Composite cost [–]");
    default:
      return QObject::tr("Elevation [m]");
  }
}

bool isCostLayer(MapView::Shown shown) {
  return shown == MapView::Shown::kCriterion || shown == MapView::Shown::kComposite;
}

// Finite values' range, or none.
std::optional<std::pair<double, double>> rangeOf(const std::vector<float>& values) {
  double lo = INFINITY, hi = -INFINITY;
  for (float v : values)
    if (std::isfinite(v)) lo = std::min(lo, double(v)), hi = std::max(hi, double(v));
  if (!(hi >= lo)) return std::nullopt;
  return std::pair{lo, hi};
}

}  // namespace

MapView::MapView(QWidget* parent) : QWidget(parent), layer_box_(new QComboBox(this)) {
  layer_box_->addItems({tr("Elevation [m]"), tr("Sigma [m]"),
                        tr("Known / oblique / unknown / shadow"),
                        tr("Footfall criterion (roughness)"), tr("Composite cost")});
  layer_box_->adjustSize();  // no layout sizes it: wide enough for the longest layer's name
  layer_box_->move(kMargin, kMargin);
  layer_box_->setToolTip(tr("Map layer shown"));
  connect(layer_box_, &QComboBox::currentIndexChanged, this, [this](int i) { setShown(Shown(i)); });
  setMouseTracking(true);
  setMinimumSize(320, 320);
}

void MapView::setMap(const terrain::ElevationMap& map) {
  map_ = map;
  recolor();
}

void MapView::clear() {
  map_.reset();
  recolor();
}

void MapView::setProposal(const std::optional<executive::StepProposal>& proposal) {
  proposal_ = proposal;
  recolor();  // the view follows the rover
}

void MapView::setRover(const std::optional<RoverDisplay>& rover) {
  const Box2 before = viewBox();
  rover_ = rover;
  const Box2 after = viewBox();
  // The feet and the CSP are drawn over the map: only a view that follows
  // the rover elsewhere needs the map coloured again.
  if (!colored_.isNull() && after.x_min == before.x_min && after.y_min == before.y_min)
    return update();
  recolor();
}

void MapView::setShown(Shown layer) {
  shown_ = layer;
  if (layer_box_->currentIndex() != int(layer)) layer_box_->setCurrentIndex(int(layer));
  recolor();
}

Box2 MapView::viewBox() const {
  Eigen::Vector2d centre(0, 0);
  if (proposal_)
    centre = proposal_->from.body.xy;
  else if (rover_)
    centre = rover_->stance.body.xy;
  return {centre.x() - kHalfViewM, centre.y() - kHalfViewM, centre.x() + kHalfViewM,
          centre.y() + kHalfViewM};
}

QRectF MapView::mapRect() const {
  const double side =
      std::max(10.0, std::min(width() - 2.0 * kMargin - kBarSpace,
                              height() - double(kTop) - kMargin - kReadoutHeight - kMargin));
  return {double(kMargin), double(kTop), side, side};
}

QPointF MapView::widgetPointOf(const Eigen::Vector2d& w) const {
  const Box2 b = viewBox();
  const QRectF r = mapRect();
  return {r.left() + (w.x() - b.x_min) / (b.x_max - b.x_min) * r.width(),
          r.bottom() - (w.y() - b.y_min) / (b.y_max - b.y_min) * r.height()};  // north up
}

std::optional<Eigen::Vector2d> MapView::worldPointAt(const QPointF& p) const {
  const QRectF r = mapRect();
  if (!r.contains(p)) return std::nullopt;
  const Box2 b = viewBox();
  return Eigen::Vector2d(b.x_min + (p.x() - r.left()) / r.width() * (b.x_max - b.x_min),
                         b.y_min + (r.bottom() - p.y()) / r.height() * (b.y_max - b.y_min));
}

const footfall::ScoreMap* MapView::costShown() const {
  if (!proposal_ || !proposal_->plan.leg_costs) return nullptr;
  if (shown_ == Shown::kCriterion) return &proposal_->plan.leg_costs->roughness;
  if (shown_ == Shown::kComposite) return &proposal_->plan.leg_costs->composite;
  return nullptr;
}

// A cell's colour before any cost is laid over it: its state, or its
// value on the shown range; under a cost layer, the elevation in grey.
QColor MapView::baseColor(int r, int c, const terrain::Layer& values) const {
  const auto state = map_->state(r, c);
  if (state == terrain::CellState::kShadow) return kShadowColor;
  if (!terrain::hasHeight(state)) return kUnknownColor;
  const bool oblique = state == terrain::CellState::kOblique;
  if (shown_ == Shown::kState) return oblique ? kObliqueColor : kKnownColor;
  const double t = (values(r, c) - base_lo_) / (base_hi_ - base_lo_);
  if (isCostLayer(shown_)) return QColor::fromHslF(0.0, 0.0, 0.35 + 0.45 * std::clamp(t, 0.0, 1.0));
  const QColor color = toQColor(rendering::viridis(t));
  return oblique ? faded(color) : color;
}

// One image pixel per map cell over the view box, coloured by the layer
// on its range over the view (elevation, composite cost) or from zero
// (sigma, the criterion's normalised cost).
void MapView::recolor() {
  colored_ = QImage();
  if (!map_) return update();
  const GridSpec& g = map_->grid();
  const Box2 b = viewBox();
  const int cols = int(std::lround((b.x_max - b.x_min) / g.resolution));
  const int rows = int(std::lround((b.y_max - b.y_min) / g.resolution));
  const auto& values =
      map_->layer(shown_ == Shown::kSigma ? terrain::layer::kSigma : terrain::layer::kElevation);
  auto worldAt = [&](int r, int c) {
    return Eigen::Vector2d(b.x_min + (c + 0.5) * g.resolution, b.y_max - (r + 0.5) * g.resolution);
  };
  std::vector<float> seen;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const Eigen::Vector2d w = worldAt(r, c);
      if (const auto cell = g.cellAt(w.x(), w.y()); cell && map_->hasHeight(cell->row, cell->col))
        seen.push_back(values(cell->row, cell->col));
    }
  const auto seen_range = rangeOf(seen);
  scale_known_ = seen_range.has_value();
  const auto base = seen_range.value_or(std::pair{0.0, 1.0});
  base_lo_ = shown_ == Shown::kSigma ? 0.0 : base.first;
  base_hi_ = std::max(base.second, base_lo_ + 1e-3);
  lo_ = base_lo_, hi_ = base_hi_;
  const footfall::ScoreMap* cost = costShown();
  if (cost) {
    const auto& s = cost->score;
    const auto range = rangeOf(std::vector<float>(s.data(), s.data() + s.size()));
    scale_known_ = shown_ == Shown::kCriterion || range.has_value();
    lo_ = shown_ == Shown::kCriterion ? 0.0 : range.value_or(std::pair{0.0, 1.0}).first;
    hi_ = shown_ == Shown::kCriterion ? 1.0 : range.value_or(std::pair{0.0, 1.0}).second;
    hi_ = std::max(hi_, lo_ + 1e-3);
  }
  colored_ = QImage(cols, rows, QImage::Format_RGB32);
  for (int r = 0; r < rows; ++r) {
    auto* line = reinterpret_cast<QRgb*>(colored_.scanLine(r));
    for (int c = 0; c < cols; ++c) {
      const Eigen::Vector2d w = worldAt(r, c);
      const auto cell = g.cellAt(w.x(), w.y());
      QColor color = cell ? baseColor(cell->row, cell->col, values) : kUnknownColor;
      if (const auto in = cost ? cost->grid.cellAt(w.x(), w.y()) : std::nullopt) {
        const float v = cost->score(in->row, in->col);
        color = std::isfinite(v) ? toQColor(rendering::viridis((v - lo_) / (hi_ - lo_)))
                                 : kCannotStandColor;
      }
      line[c] = color.rgb();
    }
  }
  update();
}

void MapView::paintEvent(QPaintEvent*) {
  QPainter p(this);
  p.fillRect(rect(), palette().window());
  if (colored_.isNull()) {
    p.drawText(rect(), Qt::AlignCenter, tr("No terrain map yet: start a walk"));
    return;
  }
  p.drawImage(mapRect(), colored_);
  p.setPen(palette().windowText().color());
  p.drawRect(mapRect());
  drawProposal(p);
  drawColorBar(p);
  if (isCostLayer(shown_) && !costShown()) {
    p.setPen(Qt::white);
    p.drawText(mapRect().adjusted(0, 8, 0, 0), Qt::AlignHCenter | Qt::AlignTop,
               proposal_ ? tr("This step moves the body only: no foothold cost map")
                         : tr("No step proposed: no cost map to show"));
    p.setPen(palette().windowText().color());
  }
  const Box2 b = viewBox();
  const QString extent = tr("%1 m x %2 m, north up")
                             .arg(b.x_max - b.x_min, 0, 'f', 0)
                             .arg(b.y_max - b.y_min, 0, 'f', 0);
  const QString caption =
      footholdEditable() ? tr("%1; click to move the proposed foothold").arg(extent) : extent;
  p.drawText(
      QRectF(kMargin, height() - kMargin - kReadoutHeight, width() - 2 * kMargin, kReadoutHeight),
      Qt::AlignLeft | Qt::AlignVCenter, readout_.isEmpty() ? caption : readout_);
}

void MapView::drawColorBar(QPainter& p) const {
  const QRectF m = mapRect();
  const QRectF bar(m.right() + 14, m.top() + 38, kBarWidth, m.height() * 0.6);
  if (shown_ == Shown::kState) {
    const std::pair<QColor, QString> keys[] = {{kKnownColor, tr("known")},
                                               {kObliqueColor, tr("oblique")},
                                               {kUnknownColor, tr("unknown")},
                                               {kShadowColor, tr("shadow")}};
    double y = m.top() + 38;
    for (const auto& [color, name] : keys) {
      p.fillRect(QRectF(bar.left(), y, kBarWidth, 12), color);
      p.drawText(QPointF(bar.left() + kBarWidth + 4, y + 11), name);
      y += 20;
    }
    return;
  }
  p.setPen(palette().windowText().color());
  if (scale_known_)
    paintColorBar(p, bar, lo_, hi_);
  else  // a scale of made-up values would read as a measurement
    p.drawText(bar.adjusted(0, 0, kBarSpace - kBarWidth - 20, 0),
               Qt::AlignLeft | Qt::AlignTop | Qt::TextWordWrap, tr("no value in view"));
  p.drawText(QRectF(m.right() + 6, m.top(), width() - m.right() - 8, 34),
             Qt::AlignLeft | Qt::AlignTop | Qt::TextWordWrap, layerUnit(shown_));
  const QRectF none(bar.left(), bar.bottom() + 10, kBarWidth, 10);
  p.fillRect(none, kUnknownColor);
  p.drawText(QPointF(none.right() + 4, none.bottom()), tr("unknown"));
  p.fillRect(none.translated(0, 16), kShadowColor);
  p.drawText(QPointF(none.right() + 4, none.bottom() + 16), tr("shadow"));
  if (!isCostLayer(shown_)) {
    p.fillRect(none.translated(0, 32), faded(toQColor(rendering::viridis(0.5))));
    p.drawText(QPointF(none.right() + 4, none.bottom() + 32), tr("oblique"));
    return;
  }
  p.fillRect(none.translated(0, 32), kCannotStandColor);
  p.drawText(QPointF(none.right() + 4, none.bottom() + 32), tr("cannot stand"));
}

// The proposed step's starting stance with its foothold (a red ring;
// orange when an interlock failed), or the reported stance.
void MapView::drawProposal(QPainter& p) const {
  if (rover_) drawRover(p, *rover_);
  if (!proposal_) return;
  drawPaths(p);
  if (proposal_->plan.leg < 0) return;
  p.save();
  p.setRenderHint(QPainter::Antialiasing);
  const QPointF foot = widgetPointOf(proposal_->plan.foothold.head<2>());
  p.setPen(QPen(proposal_->interlocks.passed() ? QColor(255, 60, 60) : QColor(255, 160, 0), 3));
  p.drawEllipse(foot, 7, 7);
  p.restore();
}

// The body's path (white, dashed, to an arrowhead) and the recovering
// foot's (red), as planned.
void MapView::drawPaths(QPainter& p) const {
  const auto& plan = proposal_->plan;
  p.save();
  p.setRenderHint(QPainter::Antialiasing);
  if (plan.body_path.size() >= 2) {
    QPolygonF body;
    for (const auto& pose : plan.body_path) body << widgetPointOf(pose.xy);
    p.setPen(QPen(Qt::white, 2, Qt::DashLine));
    p.drawPolyline(body);
    const QPointF tip = body.back(), from = body[body.size() - 2];
    const double angle = std::atan2(tip.y() - from.y(), tip.x() - from.x());
    p.setPen(QPen(Qt::white, 2));
    for (double side : {-1.0, 1.0})
      p.drawLine(tip,
                 tip - 9 * QPointF(std::cos(angle + side * 0.5), std::sin(angle + side * 0.5)));
  }
  if (!proposal_->foot_path.empty()) {
    QPolygonF foot;
    for (const auto& q : proposal_->foot_path) foot << widgetPointOf(q.head<2>());
    p.setPen(QPen(QColor(255, 90, 90), 2));
    p.drawPolyline(foot);
  }
  p.restore();
}

// Supporting feet white, lifted feet hollow, the conservative support
// polygon of the supporting feet (cyan), the body centre as a cross.
void MapView::drawRover(QPainter& p, const RoverDisplay& rover) const {
  const auto& stance = rover.stance;
  const auto& csp = rover.support_polygon;
  p.save();
  p.setRenderHint(QPainter::Antialiasing);
  if (!csp.empty()) {
    QPolygonF polygon;
    for (const auto& v : csp) polygon << widgetPointOf(v);
    p.setPen(QPen(QColor(0, 230, 255), 2));
    p.setBrush(QColor(0, 230, 255, 40));
    p.drawPolygon(polygon);
  }
  p.setPen(QPen(Qt::black, 1));
  for (std::size_t i = 0; i < stance.feet.size(); ++i) {
    p.setBrush(stance.supporting[i] ? QBrush(Qt::white) : QBrush(Qt::NoBrush));
    p.drawEllipse(widgetPointOf(stance.feet[i].head<2>()), 4, 4);
  }
  p.setBrush(Qt::NoBrush);
  p.setPen(QPen(Qt::white, 2));
  const QPointF body = widgetPointOf(stance.body.xy);
  p.drawLine(body - QPointF(6, 0), body + QPointF(6, 0));
  p.drawLine(body - QPointF(0, 6), body + QPointF(0, 6));
  p.restore();
}

void MapView::mouseMoveEvent(QMouseEvent* e) {
  const auto w = worldPointAt(e->position());
  QString text;
  if (w && map_) {
    text = tr("x %1, y %2 m").arg(w->x(), 0, 'f', 2).arg(w->y(), 0, 'f', 2);
    if (const auto cell = map_->grid().cellAt(w->x(), w->y())) {
      const int r = cell->row, c = cell->col;
      if (const auto* cost = costShown())
        if (const auto in = cost->grid.cellAt(w->x(), w->y())) {
          const float v = cost->score(in->row, in->col);
          text +=
              std::isfinite(v)
                  ? tr(" | %1 cost %2").arg(QString::fromStdString(cost->name)).arg(v, 0, 'f', 3)
                  : tr(" | the foot cannot stand here");
        }
      switch (map_->state(r, c)) {
        case terrain::CellState::kKnown:
        case terrain::CellState::kOblique:
          text += tr(" | elevation %1 m, sigma %2 m")
                      .arg(map_->elevation(r, c), 0, 'f', 3)
                      .arg(map_->sigma(r, c), 0, 'f', 3);
          // Grazing ground or a shadow's side: what lies between its samples was barely seen.
          if (!map_->isKnown(r, c)) text += tr(", seen obliquely: not to stand on");
          break;
        case terrain::CellState::kShadow:
          text += tr(" | range shadow");
          break;
        case terrain::CellState::kUnknown:
          text += tr(" | unknown");
          break;
      }
    }
  }
  if (text != readout_) {
    readout_ = text;
    emit readoutChanged(text);
    update();
  }
}

void MapView::setFootholdEditable(bool on) {
  foothold_editable_ = on;
  update();
}

bool MapView::footholdEditable() const {
  return foothold_editable_ && proposal_ && proposal_->plan.leg >= 0;
}

void MapView::mousePressEvent(QMouseEvent* e) {
  const auto w = worldPointAt(e->position());
  if (e->button() == Qt::LeftButton && w && footholdEditable())
    emit footholdClicked(proposal_->id, w->x(), w->y());
}

}  // namespace ambler::widgets
