#include "executive/ScanMatching.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "core/Format.h"

namespace ambler::executive {

Eigen::Isometry3d PoseCorrection::transform() const {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation() = Eigen::Vector3d(shift.x(), shift.y(), dz_m);
  return t;
}

PoseCorrection PoseCorrection::inverse() const {
  return {-(Eigen::Rotation2Dd(-yaw_rad) * shift), -yaw_rad, -dz_m};
}

PoseCorrection PoseCorrection::operator*(const PoseCorrection& first) const {
  return {Eigen::Rotation2Dd(yaw_rad) * first.shift + shift, yaw_rad + first.yaw_rad,
          dz_m + first.dz_m};
}

gait::BodyPose PoseCorrection::apply(gait::BodyPose body) const {
  body.xy = Eigen::Rotation2Dd(yaw_rad) * body.xy + shift;
  body.heading_rad += yaw_rad;
  body.link_z += dz_m;
  return body;
}

gait::Stance PoseCorrection::apply(gait::Stance stance) const {
  stance.body = apply(stance.body);
  const Eigen::Isometry3d t = transform();
  for (auto& foot : stance.feet) foot = t * foot;
  return stance;
}

void validate(const ScanMatchOptions& o) {
  auto positive = [](double v, const char* name) {
    if (!(v > 0) || !std::isfinite(v))
      throw std::invalid_argument(std::string("scan match: ") + name + " must be positive");
  };
  if (o.max_iterations < 1) throw std::invalid_argument("scan match: max_iterations must be >= 1");
  if (o.min_points < 4) throw std::invalid_argument("scan match: min_points must be >= 4");
  positive(o.min_step_m, "min_step_m");
  positive(o.point_sigma_floor_m, "point_sigma_floor_m");
  positive(o.robust_k, "robust_k");
  positive(o.max_slope, "max_slope");
  positive(o.max_rms_m, "max_rms_m");
  positive(o.max_sigma_xy_m, "max_sigma_xy_m");
  positive(o.max_sigma_yaw_rad, "max_sigma_yaw_rad");
}

namespace {

struct MapSample {
  double height, sigma;
  Eigen::Vector2d gradient;
};

struct Bilinear {
  double height, sigma;
};

std::optional<Bilinear> bilinear(const terrain::ElevationMap& map, const Eigen::Vector2d& xy) {
  const GridSpec& g = map.grid();
  const double fx = (xy.x() - g.origin_x) / g.resolution - 0.5;
  const double fy = (xy.y() - g.origin_y) / g.resolution - 0.5;
  const int c = int(std::floor(fx)), r = int(std::floor(fy));
  if (r < 0 || c < 0 || r + 1 >= g.rows || c + 1 >= g.cols) return std::nullopt;
  if (!map.hasHeight(r, c) || !map.hasHeight(r, c + 1) || !map.hasHeight(r + 1, c) ||
      !map.hasHeight(r + 1, c + 1))
    return std::nullopt;
  const double u = fx - c, v = fy - r;
  const double h00 = map.elevation(r, c), h01 = map.elevation(r, c + 1);
  const double h10 = map.elevation(r + 1, c), h11 = map.elevation(r + 1, c + 1);
  return Bilinear{(1 - v) * ((1 - u) * h00 + u * h01) + v * ((1 - u) * h10 + u * h11),
                  std::max({map.sigma(r, c), map.sigma(r, c + 1), map.sigma(r + 1, c),
                            map.sigma(r + 1, c + 1)})};
}

// The height where the map knows the ground around `xy`, and its gradient
// as central differences a cell either side: the bilinear patch's own
// gradient jumps at cell edges, and Gauss-Newton then flips between them.
std::optional<MapSample> sample(const terrain::ElevationMap& map, const Eigen::Vector2d& xy) {
  const double d = map.grid().resolution;
  const auto at = bilinear(map, xy);
  const auto east = bilinear(map, xy + Eigen::Vector2d(d, 0)),
             west = bilinear(map, xy - Eigen::Vector2d(d, 0));
  const auto north = bilinear(map, xy + Eigen::Vector2d(0, d)),
             south = bilinear(map, xy - Eigen::Vector2d(0, d));
  if (!at || !east || !west || !north || !south) return std::nullopt;
  return MapSample{
      at->height, at->sigma,
      Eigen::Vector2d(east->height - west->height, north->height - south->height) / (2 * d)};
}

// Parameters (dx, dy, dyaw, dz): a turn by dyaw about the vertical through
// `centre`, then a shift.
using Vector4 = Eigen::Matrix<double, 4, 1>;
using Matrix4 = Eigen::Matrix<double, 4, 4>;

struct Point {
  Eigen::Vector3d world;  // placed by the prior
  double sigma;           // the scanner's range noise there
};

struct NormalEquations {
  Matrix4 information = Matrix4::Zero();
  Vector4 gradient = Vector4::Zero();
  double weighted_squares = 0.0, squares = 0.0;
  int points = 0;
};

NormalEquations linearise(const std::vector<Point>& points, const terrain::ElevationMap& map,
                          const Eigen::Vector2d& centre, const Vector4& x, double robust_k,
                          double max_slope) {
  NormalEquations n;
  const Eigen::Rotation2Dd turn(x(2));
  for (const auto& p : points) {
    const Eigen::Vector2d arm = turn * (p.world.head<2>() - centre);
    const Eigen::Vector2d xy = centre + arm + x.head<2>();
    const auto s = sample(map, xy);
    if (!s) continue;
    if (s->gradient.norm() > max_slope) continue;
    const double residual = p.world.z() + x(3) - s->height;
    const double sigma = std::hypot(p.sigma, double(s->sigma));
    double w = 1.0 / (sigma * sigma);
    if (std::abs(residual) > robust_k * sigma) w *= robust_k * sigma / std::abs(residual);
    const Eigen::Vector2d tangent(-arm.y(), arm.x());
    const Vector4 j(-s->gradient.x(), -s->gradient.y(), -s->gradient.dot(tangent), 1.0);
    n.information.noalias() += w * j * j.transpose();
    n.gradient.noalias() += w * residual * j;
    n.weighted_squares += w * residual * residual;
    n.squares += residual * residual;
    ++n.points;
  }
  return n;
}

// The scan's returns on ground no steeper than `max_slope`, judged by the
// surface across each pixel's neighbours in the image (one-sided at a
// missing neighbour), and with no steep return next to them along the line
// of sight (the neighbouring rows). The map's cells round a small rock off,
// and the scan samples only the faces turned towards it: left in, those
// points, and the flanks just before and behind them, pull the scan towards
// the rocks' middles, along the line of sight.
std::vector<Point> levelReturns(const sensor::RangeImage& scan, const Eigen::Isometry3d& to_world,
                                double floor_m, double max_slope) {
  const int rows = scan.rows(), cols = scan.cols();
  std::vector<Eigen::Vector3d> world(std::size_t(rows) * cols,
                                     Eigen::Vector3d::Constant(std::nan("")));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      if (scan.hasReturn(r, c))
        world[std::size_t(r) * cols + c] = to_world * scan.pointInSensor(r, c);
  const auto at = [&](int r, int c) -> const Eigen::Vector3d* {
    if (r < 0 || c < 0 || r >= rows || c >= cols) return nullptr;
    const auto& p = world[std::size_t(r) * cols + c];
    return p.allFinite() ? &p : nullptr;
  };
  const auto across = [](const Eigen::Vector3d* before, const Eigen::Vector3d& here,
                         const Eigen::Vector3d* after) -> std::optional<Eigen::Vector3d> {
    if (!before && !after) return std::nullopt;
    return (after ? *after : here) - (before ? *before : here);
  };
  enum class Surface : std::uint8_t { unjudged, level, steep };
  std::vector<Surface> surface(world.size(), Surface::unjudged);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const Eigen::Vector3d* here = at(r, c);
      if (!here) continue;
      const auto down = across(at(r - 1, c), *here, at(r + 1, c));
      const auto right = across(at(r, c - 1), *here, at(r, c + 1));
      if (!down || !right) continue;
      const Eigen::Vector3d normal = down->cross(*right);
      surface[std::size_t(r) * cols + c] =
          normal.head<2>().norm() <= max_slope * std::abs(normal.z()) ? Surface::level
                                                                      : Surface::steep;
    }
  const auto steep = [&](int r, int c) {
    return r >= 0 && r < rows && surface[std::size_t(r) * cols + c] == Surface::steep;
  };
  std::vector<Point> points;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      if (surface[std::size_t(r) * cols + c] != Surface::level) continue;
      if (steep(r - 1, c) || steep(r + 1, c)) continue;
      const double range = scan.at(r, c);
      points.push_back({*at(r, c), scan.range_sigma_k * range * range + floor_m});
    }
  return points;
}

ScanMatch refuse(ScanMatch m, std::string why) {
  m.accepted = false;
  m.refused = std::move(why);
  return m;
}

// x_map = centre + R(dyaw) (x_prior - centre) + d, after the prior.
PoseCorrection moved(const PoseCorrection& prior, const Eigen::Vector2d& centre,
                     const ScanOffset& x) {
  const Eigen::Rotation2Dd turn(x(2));
  return {turn * (prior.shift - centre) + centre + x.head<2>(), prior.yaw_rad + x(2),
          prior.dz_m + x(3)};
}

}  // namespace

ScanMatch matchScanToMap(const sensor::RangeImage& scan, const terrain::ElevationMap& map,
                         const PoseCorrection& prior, const ScanMatchOptions& o) {
  validate(o);
  const auto t0 = std::chrono::steady_clock::now();
  ScanMatch m;
  m.correction = prior;
  auto done = [&](ScanMatch r) {
    r.ms = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  };
  const Eigen::Isometry3d from = prior.transform() * scan.sensor_to_world;
  const Eigen::Vector2d centre = from.translation().head<2>();
  const std::vector<Point> points = levelReturns(scan, from, o.point_sigma_floor_m, o.max_slope);
  double reach = 0.0;
  for (const auto& p : points) reach = std::max(reach, (p.world.head<2>() - centre).norm());
  Vector4 x = Vector4::Zero();
  NormalEquations n;
  bool converged = false;
  for (m.iterations = 1; m.iterations <= o.max_iterations && !converged; ++m.iterations) {
    n = linearise(points, map, centre, x, o.robust_k, o.max_slope);
    if (n.points < o.min_points) break;
    const Vector4 step = n.information.ldlt().solve(-n.gradient);
    if (!step.allFinite()) break;
    x += step;
    converged = step.head<2>().norm() + std::abs(step(2)) * reach < o.min_step_m &&
                std::abs(step(3)) < o.min_step_m;
  }
  m.iterations = std::min(m.iterations - 1, o.max_iterations);
  n = linearise(points, map, centre, x, o.robust_k, o.max_slope);
  m.points = n.points;
  if (n.points < o.min_points)
    return done(refuse(m, std::to_string(n.points) + " scan points over known map, fewer than " +
                              std::to_string(o.min_points)));
  m.rms_m = std::sqrt(n.squares / n.points);
  // The residuals' own scale, not the assumed sigmas, sets the covariance.
  const double scale = n.weighted_squares / std::max(1, n.points - 4);
  const Matrix4 covariance = scale * n.information.inverse();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> xy(covariance.topLeftCorner<2, 2>());
  m.sigma_xy_m = std::sqrt(std::max(0.0, xy.eigenvalues()(1)));
  m.sigma_yaw_rad = std::sqrt(std::max(0.0, covariance(2, 2)));
  m.offset = x;
  m.covariance = covariance;
  if (!covariance.allFinite() || m.sigma_xy_m > o.max_sigma_xy_m ||
      m.sigma_yaw_rad > o.max_sigma_yaw_rad)
    return done(refuse(m, "ground does not hold the scan in place (sigma " +
                              fixed(m.sigma_xy_m, 3) + " m, " +
                              fixed(m.sigma_yaw_rad * 180 / M_PI, 3) + " deg)"));
  if (!converged)
    return done(refuse(m, "no convergence in " + std::to_string(o.max_iterations) + " iterations"));
  if (m.rms_m > o.max_rms_m)
    return done(refuse(m, "rms " + fixed(m.rms_m, 3) + " m above " + fixed(o.max_rms_m, 3) + " m"));
  m.correction = moved(prior, centre, x);
  m.change_m = x.head<2>().norm();
  m.change_rad = std::abs(x(2));
  m.accepted = true;
  return done(m);
}

PoseCorrector::PoseCorrector(PoseCorrectorOptions options) : opt_(std::move(options)) {
  validate(opt_.match);
  if (!(opt_.match_sigma_scale > 0) || !(opt_.max_chi2 > 0) || !(opt_.drift.position_m >= 0) ||
      !(opt_.drift.heading_rad >= 0) || !(opt_.drift.height_m >= 0))
    throw std::invalid_argument(
        "pose corrector: drift must be >= 0, match_sigma_scale and max_chi2 positive");
}

ScanMatch PoseCorrector::correct(const sensor::RangeImage& scan, const terrain::ElevationMap& map) {
  const Eigen::Vector2d scanner = scan.sensor_to_world.translation().head<2>();
  const double travelled = last_scanner_ ? (scanner - *last_scanner_).norm() : 0.0;
  last_scanner_ = scanner;
  const auto& d = opt_.drift;
  covariance_.diagonal() +=
      travelled * ScanOffset(d.position_m * d.position_m, d.position_m * d.position_m,
                             d.heading_rad * d.heading_rad, d.height_m * d.height_m);
  ScanMatch m = matchScanToMap(scan, map, correction_, opt_.match);
  if (!m.accepted) {
    m.correction = correction_;
    return m;
  }
  const double s2 = opt_.match_sigma_scale * opt_.match_sigma_scale;
  const ScanOffsetCovariance innovation = covariance_ + s2 * m.covariance;
  m.chi2 = m.offset.dot(innovation.ldlt().solve(m.offset));
  if (!(m.chi2 <= opt_.max_chi2)) {
    const bool agrees = disputed_ &&
                        (m.offset.head<2>() - disputed_->head<2>()).norm() <= opt_.agree_m &&
                        std::abs(m.offset(2) - (*disputed_)(2)) <= opt_.agree_rad;
    disputes_ = agrees ? disputes_ + 1 : 1;
    disputed_ = m.offset;
    if (disputes_ < opt_.relocate_after) {
      m.disputed = true;
      m.correction = correction_;
      m.change_m = m.change_rad = 0.0;
      return refuse(m, "the match disagrees with dead reckoning (chi-square " + fixed(m.chi2, 1) +
                           " > " + fixed(opt_.max_chi2, 1) + "), " + std::to_string(disputes_) +
                           " of " + std::to_string(opt_.relocate_after) + " agreeing");
    }
    m.relocated = true;
    covariance_ = s2 * m.covariance;
    return commit(m, scan, m.offset);
  }
  disputes_ = 0;
  disputed_.reset();
  const ScanOffsetCovariance gain = covariance_ * innovation.inverse();
  covariance_ = (ScanOffsetCovariance::Identity() - gain) * covariance_;
  covariance_ = 0.5 * (covariance_ + covariance_.transpose()).eval();
  return commit(m, scan, gain * m.offset);
}

ScanMatch PoseCorrector::commit(ScanMatch m, const sensor::RangeImage& scan,
                                const ScanOffset& applied) {
  const Eigen::Vector2d centre =
      (correction_.transform() * scan.sensor_to_world).translation().head<2>();
  correction_ = moved(correction_, centre, applied);
  m.correction = correction_;
  m.change_m = applied.head<2>().norm();
  m.change_rad = std::abs(applied(2));
  return m;
}

}  // namespace ambler::executive
