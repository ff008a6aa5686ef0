#include "sampling/DeformableContour.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

namespace ambler::sampling {

namespace {

constexpr int kDirections = 16;
constexpr double kDirectionStep = M_PI / 20;  // the 16 directions span +-67.5 deg around the normal

// The ellipse with the polygon's centroid and second moments of area:
// (p - centre)^T a (p - centre) = 1.
struct Ellipse {
  Eigen::Vector2d centre{0, 0};
  Eigen::Matrix2d a = Eigen::Matrix2d::Identity();
  double mean_radius = 1.0;
};

double signedArea(const std::vector<Eigen::Vector2d>& p) {
  double twice = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& u = p[i];
    const auto& v = p[(i + 1) % p.size()];
    twice += u.x() * v.y() - v.x() * u.y();
  }
  return twice / 2;
}

// Green's theorem gives the area integrals of x, y, x^2, y^2, xy; a uniform
// ellipse with semi-axes a, b has covariance eigenvalues a^2/4, b^2/4.
Ellipse fitEllipse(const std::vector<Eigen::Vector2d>& p) {
  double area = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double x0 = p[i].x(), y0 = p[i].y();
    const double x1 = p[(i + 1) % p.size()].x(), y1 = p[(i + 1) % p.size()].y();
    const double cross = x0 * y1 - x1 * y0;
    area += cross;
    sx += (x0 + x1) * cross, sy += (y0 + y1) * cross;
    sxx += (x0 * x0 + x0 * x1 + x1 * x1) * cross;
    syy += (y0 * y0 + y0 * y1 + y1 * y1) * cross;
    sxy += (x0 * y1 + 2 * x0 * y0 + 2 * x1 * y1 + x1 * y0) * cross;
  }
  area /= 2;
  Ellipse e;
  if (std::abs(area) < 1e-6) {
    for (const auto& q : p) e.centre += q / double(p.size());
    return e;
  }
  e.centre = {sx / (6 * area), sy / (6 * area)};
  Eigen::Matrix2d cov;
  cov(0, 0) = sxx / (12 * area) - e.centre.x() * e.centre.x();
  cov(1, 1) = syy / (12 * area) - e.centre.y() * e.centre.y();
  cov(0, 1) = cov(1, 0) = sxy / (24 * area) - e.centre.x() * e.centre.y();
  const double det = cov.determinant();
  if (!(det > 1e-9)) return e;
  e.a = (4.0 * cov).inverse();
  e.mean_radius = 2.0 * std::pow(det, 0.25);
  return e;
}

struct Hit {
  bool found = false;
  double distance = 0;
  Eigen::Vector2d direction{0, 0};
};

// The nearest feature pixel along 16 directions around `normal`, within r_max.
Hit nearestFeature(const FeatureMap& f, const Eigen::Vector2d& p, const Eigen::Vector2d& normal,
                   double r_max) {
  Hit best;
  const double base = std::atan2(normal.y(), normal.x());
  for (int k = 0; k < kDirections; ++k) {
    const double angle = base + (k - (kDirections - 1) / 2.0) * kDirectionStep;
    const Eigen::Vector2d d(std::cos(angle), std::sin(angle));
    for (double s = 1.0; s <= r_max && (!best.found || s < best.distance); s += 1.0) {
      const Eigen::Vector2d q = p + s * d;
      if (f.isFeature(int(std::lround(q.y())), int(std::lround(q.x())))) {
        best = {true, s, d};
        break;
      }
    }
  }
  return best;
}

// The sum of the paper's three forces at `p`; positive moves it outward.
double totalForce(const Hit& hit, const Eigen::Vector2d& p, const Eigen::Vector2d& seed,
                  const Ellipse& e, const ContourOptions& o) {
  // A point stops next to its feature: stepping onto it would let the
  // resampled points between two arrived ones slip through gaps.
  const double feature = !hit.found ? o.free_growth : hit.distance <= 1.0 ? -1.0 : 1.0;
  // Towards the seed, from half the largest expected radius on.
  const double reach = (p - seed).norm() / o.r_max_px;
  const double centre = -std::max(0.0, (reach - 0.5) / 0.5);
  // Towards the ellipse: eq. 3 for the distance, relative to its size.
  const Eigen::Vector2d d = p - e.centre;
  const double q = d.dot(e.a * d);
  const double distance = std::abs(q - 1.0) / std::max(2.0 * (e.a * d).norm(), 1e-9);
  const double pull = std::min(1.0, distance / (o.k_internal * e.mean_radius));
  const double internal = q > 1.0 ? -pull : 0.5 * pull;
  return feature + centre + internal;
}

std::vector<Eigen::Vector2d> resample(const std::vector<Eigen::Vector2d>& p, double spacing) {
  std::vector<double> along{0.0};
  for (std::size_t i = 0; i < p.size(); ++i)
    along.push_back(along.back() + (p[(i + 1) % p.size()] - p[i]).norm());
  const int n = std::max(8, int(std::lround(along.back() / spacing)));
  std::vector<Eigen::Vector2d> out;
  std::size_t seg = 0;
  for (int k = 0; k < n; ++k) {
    const double s = along.back() * k / n;
    while (seg + 1 < along.size() - 1 && along[seg + 1] < s) ++seg;
    const double len = along[seg + 1] - along[seg];
    const double t = len > 0 ? (s - along[seg]) / len : 0.0;
    out.push_back(p[seg] + t * (p[(seg + 1) % p.size()] - p[seg]));
  }
  return out;
}

}  // namespace

void validate(const ContourOptions& o) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("contour option " + what);
  };
  require(o.r_max_px >= 3 && o.r_max_px <= 1000, "r_max_px must be in [3, 1000]");
  require(o.k_internal > 0 && o.k_internal <= 10, "k_internal must be in (0, 10]");
  require(o.spacing_px >= 0.5 && o.spacing_px <= 20, "spacing_px must be in [0.5, 20]");
  require(o.max_iterations >= 1 && o.max_iterations <= 100000,
          "max_iterations must be in [1, 100000]");
  require(o.free_growth >= 0 && o.free_growth <= 1, "free_growth must be in [0, 1]");
}

double Contour::areaPx() const { return std::abs(signedArea(points)); }

Contour growContour(const FeatureMap& features, const Eigen::Vector2d& seed,
                    const ContourOptions& o, const ContourObserver& observer) {
  validate(o);
  // Checked before rounding: a seed far off the image does not fit in an int.
  const Eigen::Vector2d pixel = seed.array().round();
  if (!(pixel.y() >= 0 && pixel.x() >= 0 && pixel.y() < features.rows &&
        pixel.x() < features.cols)) {
    char text[96];
    std::snprintf(text, sizeof text, "seed (%g, %g) is outside the image", seed.y(), seed.x());
    throw std::invalid_argument(text);
  }
  const int row = int(pixel.y()), col = int(pixel.x());
  if (features.isFeature(row, col))
    throw std::invalid_argument("seed (" + std::to_string(row) + ", " + std::to_string(col) + ") " +
                                (features.kindAt(row, col) & kShadow
                                     ? "has no measurement (a range shadow)"
                                     : "lies on an edge") +
                                ": pick a pixel inside the rock");
  Contour contour;
  for (int k = 0; k < 8; ++k)
    contour.points.push_back(seed +
                             2.0 * Eigen::Vector2d(std::cos(k * M_PI / 4), std::sin(k * M_PI / 4)));
  Ellipse ellipse = fitEllipse(contour.points);
  for (contour.iterations = 1; contour.iterations <= o.max_iterations; ++contour.iterations) {
    const double orientation = signedArea(contour.points) >= 0 ? 1.0 : -1.0;
    const auto& p = contour.points;
    std::vector<Eigen::Vector2d> moved = p;
    int moves = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (features.isFeature(int(std::lround(p[i].y())), int(std::lround(p[i].x())))) continue;
      const Eigen::Vector2d t = p[(i + 1) % p.size()] - p[(i + p.size() - 1) % p.size()];
      const Eigen::Vector2d normal = orientation * Eigen::Vector2d(t.y(), -t.x()).normalized();
      const Hit hit = nearestFeature(features, p[i], normal, o.r_max_px);
      if (totalForce(hit, p[i], seed, ellipse, o) <= 0) continue;
      moved[i] = p[i] + (hit.found ? hit.direction : normal);  // one pixel
      ++moves;
    }
    contour.points = resample(moved, o.spacing_px);
    ellipse = fitEllipse(contour.points);
    if (observer) observer(contour);
    if (moves == 0) {
      contour.converged = true;
      break;
    }
  }
  contour.iterations = std::min(contour.iterations, o.max_iterations);
  return contour;
}

io::ByteImage contourMask(const Contour& contour, int rows, int cols, bool to_features) {
  cv::Mat mask(rows, cols, CV_8U, cv::Scalar(0));
  std::vector<cv::Point> polygon;
  for (const auto& p : contour.points)
    polygon.emplace_back(int(std::lround(p.x())), int(std::lround(p.y())));
  cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{polygon}, cv::Scalar(255));
  if (to_features) cv::dilate(mask, mask, cv::Mat::ones(3, 3, CV_8U));
  io::ByteImage out(rows, cols);
  std::copy(mask.datastart, mask.dataend, out.pixels.begin());
  return out;
}

}  // namespace ambler::sampling
