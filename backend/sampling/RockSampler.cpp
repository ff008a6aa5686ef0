#include "sampling/RockSampler.h"

#include <chrono>
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

RockSample sampleRock(const sensor::StriperImage& image, const FeatureMap& features,
                      const Eigen::Vector2d& seed, const SamplingOptions& options,
                      const ContourObserver& observer) {
  RockSample sample;
  sample.seed = seed;
  sample.contour = growContour(features, seed, options.contour, observer);
  sample.points = pointsInside(image, contourMask(sample.contour, image.rows(), image.cols()));
  if (sample.points.size() < 11)
    throw std::invalid_argument("the contour from this seed encloses " +
                                std::to_string(sample.points.size()) +
                                " measured points; a fit needs 11");
  const auto start = std::chrono::steady_clock::now();
  sample.fit = fitSuperquadric(sample.points, options.fit);
  sample.fit_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  sample.grasp = planGrasp(sample.fit.shape, image, options.gripper);
  return sample;
}

}  // namespace ambler::sampling
