#include "sampling/RockSampler.h"

#include <Eigen/QR>
#include <chrono>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

namespace ambler::sampling {

std::vector<Eigen::Vector3d> pointsInside(const sensor::StriperImage& image,
                                          const io::ByteImage& mask) {
  std::vector<Eigen::Vector3d> points;
  for (int r = 0; r < image.rows(); ++r)
    for (int c = 0; c < image.cols(); ++c)
      if (mask(r, c) && image.hasPoint(r, c)) points.push_back(image.point(r, c));
  return points;
}

namespace {

cv::Mat grown(const cv::Mat& mask, int px) {
  cv::Mat out;
  cv::dilate(mask, out, cv::Mat::ones(2 * px + 1, 2 * px + 1, CV_8U));
  return out;
}

// z = a x + b y + c through the points, refitted without those off by
// more than three median deviations (a neighbouring rock, a ripple).
Eigen::Vector3d sandPlane(const std::vector<Eigen::Vector3d>& points) {
  std::vector<Eigen::Vector3d> use = points;
  Eigen::Vector3d plane(0, 0, 0);
  for (int round = 0; round < 2 && use.size() >= 3; ++round) {
    Eigen::MatrixXd a(Eigen::Index(use.size()), 3);
    Eigen::VectorXd b(Eigen::Index(use.size()));
    for (std::size_t i = 0; i < use.size(); ++i)
      a.row(Eigen::Index(i)) << use[i].x(), use[i].y(), 1.0, b(Eigen::Index(i)) = use[i].z();
    plane = a.colPivHouseholderQr().solve(b);
    std::vector<double> off;
    for (const auto& p : points)
      off.push_back(std::abs(p.z() - plane.dot(Eigen::Vector3d(p.x(), p.y(), 1))));
    std::vector<double> sorted = off;
    std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(sorted.size() / 2),
                     sorted.end());
    const double limit = 3 * 1.4826 * sorted[sorted.size() / 2] + 1e-6;
    use.clear();
    for (std::size_t i = 0; i < points.size(); ++i)
      if (off[i] <= limit) use.push_back(points[i]);
  }
  return plane;
}

}  // namespace

void validate(const SamplingOptions& o) {
  validate(o.features);
  validate(o.contour);
  validate(o.fit);
  validate(o.seeds);
  if (o.rim_px < 0 || o.rim_px > 10)
    throw std::invalid_argument("sampling option rim_px must be in [0, 10]");
  if (!(o.sand_clearance_m >= 0 && o.sand_clearance_m < 0.1))
    throw std::invalid_argument("sampling option sand_clearance_m must be in [0, 0.1) m");
}

RockPoints rockPoints(const sensor::StriperImage& image, const Contour& contour,
                      const SamplingOptions& o) {
  const auto inner_mask = contourMask(contour, image.rows(), image.cols(), false);
  const cv::Mat inner(image.rows(), image.cols(), CV_8U,
                      const_cast<unsigned char*>(inner_mask.pixels.data()));
  const cv::Mat rim = grown(inner, o.rim_px);
  // The sand: a ring from 3 to 7 pixels beyond the contour.
  const cv::Mat ring = grown(inner, 7) & ~grown(inner, 3);
  std::vector<Eigen::Vector3d> sand;
  RockPoints rock;
  for (int r = 0; r < image.rows(); ++r)
    for (int c = 0; c < image.cols(); ++c)
      if (ring.at<std::uint8_t>(r, c) && image.hasPoint(r, c)) sand.push_back(image.point(r, c));
  const bool has_sand = sand.size() >= 10;
  const Eigen::Vector3d plane = has_sand ? sandPlane(sand) : Eigen::Vector3d::Zero();
  for (int r = 0; r < image.rows(); ++r)
    for (int c = 0; c < image.cols(); ++c) {
      if (!rim.at<std::uint8_t>(r, c) || !image.hasPoint(r, c)) continue;
      const Eigen::Vector3d p = image.point(r, c);
      const bool inside = inner.at<std::uint8_t>(r, c) != 0;
      const double above = p.z() - plane.dot(Eigen::Vector3d(p.x(), p.y(), 1));
      if (inside || (has_sand && above > o.sand_clearance_m)) rock.points.push_back(p);
    }
  if (has_sand) {
    const Eigen::Vector3d up(-plane.x(), -plane.y(), 1);
    rock.sand = Eigen::Hyperplane<double, 3>(up.normalized(), -plane.z() / up.norm());
  }
  return rock;
}

RockSample sampleRock(const sensor::StriperImage& image, const FeatureMap& features,
                      const Eigen::Vector2d& seed, const SamplingOptions& options,
                      const ContourObserver& observer) {
  RockSample sample;
  sample.seed = seed;
  validate(options);
  sample.contour = growContour(features, seed, options.contour, observer);
  auto rock = rockPoints(image, sample.contour, options);
  sample.points = std::move(rock.points);
  sample.sand = rock.sand;
  if (sample.points.size() < 11)
    throw std::invalid_argument("the contour from this seed encloses " +
                                std::to_string(sample.points.size()) +
                                " measured points; a fit needs 11");
  const auto start = std::chrono::steady_clock::now();
  sample.fit = fitSuperquadric(sample.points, options.fit, sample.sand);
  sample.fit_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  sample.grasp = planGrasp(sample.fit.shape, image, options.gripper);
  return sample;
}

}  // namespace ambler::sampling
