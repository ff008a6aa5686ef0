#include "sampling/SuperquadricFit.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ambler::sampling {

namespace {

constexpr int kParams = 11;  // a1 a2 a3 eps1 eps2 | t (3) | rotation (3)
using Row = Eigen::Matrix<double, 1, kParams>;
using Vector = Eigen::Matrix<double, kParams, 1>;
using Matrix = Eigen::Matrix<double, kParams, kParams>;
constexpr double kEpsMin = 0.1, kEpsMax = 2.0, kSizeMin = 1e-3;

// G = F^eps1 at p in the object frame (x), and its gradient over the
// parameters (rotation as a small turn applied in the object frame).
double powerF(const Superquadric& s, const Eigen::Vector3d& p, Row* dg, Eigen::Vector3d* x_out) {
  const Eigen::Matrix3d rot = s.pose.linear();
  const Eigen::Vector3d x = rot.transpose() * (p - s.pose.translation());
  if (x_out) *x_out = x;
  const double a1 = s.size.x(), a2 = s.size.y(), a3 = s.size.z(), e1 = s.eps1, e2 = s.eps2;
  constexpr double kTiny = 1e-12;
  const double ax = std::max(std::abs(x.x()) / a1, kTiny);
  const double ay = std::max(std::abs(x.y()) / a2, kTiny);
  const double az = std::max(std::abs(x.z()) / a3, kTiny);
  // Powers through exp and log: the logs are needed for the gradient anyway.
  const double lx = std::log(ax), ly = std::log(ay), lz = std::log(az);
  const double u = std::exp(2 / e2 * lx), v = std::exp(2 / e2 * ly), w = std::exp(2 / e1 * lz);
  const double sum = u + v, log_sum = std::log(sum), g = std::exp(e2 / e1 * log_sum), f = g + w;
  const double log_f = std::log(f), big_g = std::exp(e1 * log_f);
  if (!dg) return big_g;
  const double common = (2 / e1) * g / sum;  // dF/du * du/dx * x / u
  auto over = [](double value, double by) { return std::abs(by) > kTiny ? value / by : 0.0; };
  const Eigen::Vector3d df_dx(common * over(u, x.x()), common * over(v, x.y()),
                              (2 / e1) * over(w, x.z()));
  const double dg_df = e1 * big_g / f;
  const double du_de2 = u * lx * (-2 / (e2 * e2));
  const double dv_de2 = v * ly * (-2 / (e2 * e2));
  const double df_de2 = g * (log_sum / e1 + (e2 / e1) * (du_de2 + dv_de2) / sum);
  const double df_de1 = g * log_sum * (-e2 / (e1 * e1)) + w * lz * (-2 / (e1 * e1));
  (*dg)(0) = dg_df * -common * u / a1;
  (*dg)(1) = dg_df * -common * v / a2;
  (*dg)(2) = dg_df * -(2 / e1) * w / a3;
  (*dg)(3) = big_g * (log_f + e1 * df_de1 / f);
  (*dg)(4) = dg_df * df_de2;
  const Eigen::Vector3d dg_dx = dg_df * df_dx;
  dg->segment<3>(5) = -(rot * dg_dx).transpose();
  // x' = x + x cross d for a small turn d: dx/dd = [x]_x.
  Eigen::Matrix3d skew;
  skew << 0, -x.z(), x.y(), x.z(), 0, -x.x(), -x.y(), x.x(), 0;
  dg->segment<3>(8) = dg_dx.transpose() * skew;
  return big_g;
}

// The residual the options choose, and its gradient.
double residual(const Superquadric& s, const Eigen::Vector3d& p, FitResidual kind, Row* j) {
  Row dg;
  Eigen::Vector3d x;
  const double big_g = powerF(s, p, j ? &dg : nullptr, &x);
  if (kind == FitResidual::kSolina) {
    // sqrt(a1 a2 a3) (F^eps1 - 1)
    const double volume = std::sqrt(s.size.prod());
    if (j) {
      *j = volume * dg;
      for (int i = 0; i < 3; ++i) (*j)(i) += (big_g - 1) * volume / (2 * s.size[i]);
    }
    return volume * (big_g - 1);
  }
  // |x| (1 - F^(-eps1/2)): the distance to the surface along the ray from
  // the centre (Jaklic et al.), nearly Euclidean near the surface.
  const double norm = std::max(x.norm(), 1e-12), h = 1 / std::sqrt(big_g);
  if (j) {
    *j = norm * 0.5 * h * h * h * dg;
    j->segment<3>(5) -= (1 - h) * (s.pose.linear() * x / norm).transpose();
  }
  return norm * (1 - h);
}

Superquadric applyStep(const Superquadric& s, const Vector& d, double max_size) {
  Superquadric out = s;
  for (int i = 0; i < 3; ++i) out.size[i] = std::clamp(s.size[i] + d(i), kSizeMin, max_size);
  out.eps1 = std::clamp(s.eps1 + d(3), kEpsMin, kEpsMax);
  out.eps2 = std::clamp(s.eps2 + d(4), kEpsMin, kEpsMax);
  const Eigen::Vector3d turn = d.segment<3>(8);
  Eigen::Matrix3d rot = s.pose.linear();
  if (turn.norm() > 0) rot = rot * Eigen::AngleAxisd(turn.norm(), turn.normalized());
  out.pose = Eigen::Translation3d(s.pose.translation() + d.segment<3>(5)) * Eigen::Quaterniond(rot);
  return out;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Cauchy weights from the residuals' robust spread; all ones when not robust.
std::vector<double> weightsFor(const std::vector<double>& r, const FitOptions& o) {
  std::vector<double> w(r.size(), 1.0);
  if (!o.robust) return w;
  std::vector<double> abs_r(r.size());
  for (std::size_t i = 0; i < r.size(); ++i) abs_r[i] = std::abs(r[i]);
  const double scale = std::max(o.cauchy_scale * 1.4826 * median(abs_r), 1e-12);
  for (std::size_t i = 0; i < r.size(); ++i) w[i] = 1.0 / (1.0 + std::pow(r[i] / scale, 2));
  return w;
}

// The signed height of the shape's lowest point above the ground plane.
double groundGap(const Superquadric& s, const Eigen::Hyperplane<double, 3>& ground) {
  return ground.signedDistance(s.pose.translation()) - s.reach(-ground.normal());
}

double weightedCost(const Superquadric& s, const std::vector<Eigen::Vector3d>& points,
                    const std::vector<double>& w, FitResidual kind) {
  double cost = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double r = residual(s, points[i], kind, nullptr);
    cost += w[i] * r * r;
  }
  return cost;
}

}  // namespace

void validate(const FitOptions& o) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("fit option " + what);
  };
  require(o.max_iterations >= 1 && o.max_iterations <= 100000,
          "max_iterations must be in [1, 100000]");
  require(o.tolerance > 0 && o.tolerance < 1, "tolerance must be in (0, 1)");
  require(o.cauchy_scale > 0 && o.cauchy_scale <= 100, "cauchy_scale must be in (0, 100]");
  require(o.max_size_ratio >= 1 && o.max_size_ratio <= 100, "max_size_ratio must be in [1, 100]");
  require(o.resting_weight >= 0 && o.resting_weight <= 10, "resting_weight must be in [0, 10]");
}

std::vector<Eigen::Vector3d> trimmedCore(const std::vector<Eigen::Vector3d>& points, double keep) {
  std::vector<Eigen::Vector3d> core = points;
  for (int round = 0; round < 5; ++round) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& p : core) mean += p / double(core.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const auto& p : core) cov += (p - mean) * (p - mean).transpose() / double(core.size());
    const Eigen::Matrix3d inv = (cov + 1e-12 * Eigen::Matrix3d::Identity()).inverse();
    std::vector<std::pair<double, std::size_t>> d;
    for (std::size_t i = 0; i < points.size(); ++i)
      d.push_back({(points[i] - mean).dot(inv * (points[i] - mean)), i});
    const auto n = std::max<std::size_t>(11, std::size_t(keep * double(points.size())));
    std::nth_element(d.begin(), d.begin() + std::ptrdiff_t(std::min(n, d.size()) - 1), d.end());
    core.clear();
    for (std::size_t k = 0; k < std::min(n, d.size()); ++k) core.push_back(points[d[k].second]);
  }
  return core;
}

double sizeError(const Superquadric& fit, const Superquadric& truth) {
  // |cos| between each true axis (row) and each fitted axis (column).
  const Eigen::Matrix3d alignment =
      (truth.pose.linear().transpose() * fit.pose.linear()).cwiseAbs();
  std::array<int, 3> match{0, 1, 2}, best = match;
  double best_alignment = -1;
  do {
    const double sum = alignment(0, match[0]) + alignment(1, match[1]) + alignment(2, match[2]);
    if (sum > best_alignment) best_alignment = sum, best = match;
  } while (std::next_permutation(match.begin(), match.end()));
  double worst = 0;
  for (int t = 0; t < 3; ++t)
    worst = std::max(worst, std::abs(fit.size[best[std::size_t(t)]] / truth.size[t] - 1));
  return worst;
}

Superquadric momentEllipsoid(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p;
  mean /= double(points.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : points) cov += (p - mean) * (p - mean).transpose();
  cov /= double(points.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  // Object z: the principal axis nearest the vertical (rocks lie on the ground).
  int z = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(eig.eigenvectors()(2, i)) > std::abs(eig.eigenvectors()(2, z))) z = i;
  int x = z == 2 ? 1 : 2, y = 3 - x - z;
  if (eig.eigenvalues()(y) > eig.eigenvalues()(x)) std::swap(x, y);
  Eigen::Matrix3d rot;
  rot.col(0) = eig.eigenvectors().col(x);
  rot.col(2) = eig.eigenvectors().col(z) * (eig.eigenvectors()(2, z) < 0 ? -1.0 : 1.0);
  rot.col(1) = rot.col(2).cross(rot.col(0));
  Superquadric s;
  s.size = {std::sqrt(3 * eig.eigenvalues()(x)), std::sqrt(3 * eig.eigenvalues()(y)),
            std::sqrt(3 * eig.eigenvalues()(z))};
  s.size = s.size.cwiseMax(kSizeMin);
  s.eps1 = s.eps2 = 1.0;
  s.pose = Eigen::Translation3d(mean) * Eigen::Quaterniond(rot);
  return s;
}

namespace {

// The least-squares problem: the points' residuals under weights, and the
// resting prior as one more residual.
struct Problem {
  const std::vector<Eigen::Vector3d>& points;
  const FitOptions& options;
  const std::optional<Eigen::Hyperplane<double, 3>>& ground;
  double max_size = 0.0;  // no size beyond this [m]

  bool rests() const { return ground && options.resting_weight > 0; }

  double prior(const Superquadric& s) const {
    return options.resting_weight * std::sqrt(double(points.size())) * groundGap(s, *ground);
  }

  Row priorRow(const Superquadric& s) const {
    Row j;
    for (int i = 0; i < kParams; ++i) {
      Vector d = Vector::Zero();
      d(i) = 1e-6;
      j(i) = (prior(applyStep(s, d, max_size)) - prior(applyStep(s, -d, max_size))) / 2e-6;
    }
    return j;
  }

  double cost(const Superquadric& s, const std::vector<double>& w) const {
    return weightedCost(s, points, w, options.residual) + (rests() ? std::pow(prior(s), 2) : 0.0);
  }

  // Gauss-Newton's h = J'WJ and g = J'Wr at s, and the weights it used.
  std::vector<double> linearize(const Superquadric& s, Matrix& h, Vector& g) const {
    std::vector<double> r(points.size());
    std::vector<Row> jacobian(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
      r[i] = residual(s, points[i], options.residual, &jacobian[i]);
    const auto w = weightsFor(r, options);
    h.setZero(), g.setZero();
    for (std::size_t i = 0; i < points.size(); ++i) {
      h.noalias() += w[i] * jacobian[i].transpose() * jacobian[i];
      g.noalias() += w[i] * jacobian[i].transpose() * r[i];
    }
    if (rests()) {
      const Row j = priorRow(s);
      h.noalias() += j.transpose() * j;
      g.noalias() += j.transpose() * prior(s);
    }
    return w;
  }
};

void checkPoints(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < std::size_t(kParams))
    throw std::invalid_argument("superquadric fit: " + std::to_string(points.size()) +
                                " points, at least 11 needed");
  for (const auto& p : points)
    if (!p.allFinite()) throw std::invalid_argument("superquadric fit: a point is not finite");
}

double largestSize(const std::vector<Eigen::Vector3d>& points, const FitOptions& o) {
  Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  for (const auto& p : points) lo = lo.cwiseMin(p.head<2>()), hi = hi.cwiseMax(p.head<2>());
  return std::max(kSizeMin, o.max_size_ratio * 0.5 * (hi - lo).maxCoeff());
}

// Levenberg-Marquardt from fit.shape.
void refine(const Problem& problem, SuperquadricFit& fit) {
  double lambda = 1e-3;
  Matrix h;
  Vector g;
  for (fit.iterations = 0; fit.iterations < problem.options.max_iterations; ++fit.iterations) {
    const auto w = problem.linearize(fit.shape, h, g);
    const double cost = problem.cost(fit.shape, w);
    bool improved = false;
    double new_cost = cost;
    while (!improved && lambda < 1e12) {
      Matrix damped = h;
      damped.diagonal() += lambda * h.diagonal().cwiseMax(1e-12);
      const Superquadric candidate =
          applyStep(fit.shape, damped.ldlt().solve(-g), problem.max_size);
      new_cost = problem.cost(candidate, w);
      if (std::isfinite(new_cost) && new_cost < cost) {
        fit.shape = candidate;
        lambda = std::max(lambda / 3, 1e-9);
        improved = true;
      } else {
        lambda *= 4;
      }
    }
    if (!improved || cost - new_cost < problem.options.tolerance * cost) {
      fit.converged = true;
      return;
    }
  }
}

// rms_m and inlier_share over the points of weight >= 0.5.
void assess(const std::vector<Eigen::Vector3d>& points, const FitOptions& o, SuperquadricFit& fit) {
  std::vector<double> r(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    r[i] = residual(fit.shape, points[i], o.residual, nullptr);
  const auto w = weightsFor(r, o);
  double sum = 0;
  int kept = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (w[i] >= 0.5)
      sum += std::pow(residual(fit.shape, points[i], FitResidual::kRadial, nullptr), 2), ++kept;
  fit.rms_m = kept ? std::sqrt(sum / kept) : 0.0;
  fit.inlier_share = double(kept) / double(points.size());
}

}  // namespace

SuperquadricFit fitSuperquadric(const std::vector<Eigen::Vector3d>& points, const FitOptions& o,
                                const std::optional<Eigen::Hyperplane<double, 3>>& ground) {
  validate(o);
  checkPoints(points);
  const Problem problem{points, o, ground, largestSize(points, o)};
  SuperquadricFit fit;
  // The robust fit starts from the moments of the points' densest 75 %.
  fit.shape = momentEllipsoid(o.robust ? trimmedCore(points, 0.75) : points);
  fit.shape.size = fit.shape.size.cwiseMin(problem.max_size);
  refine(problem, fit);
  assess(points, o, fit);
  return fit;
}

}  // namespace ambler::sampling
