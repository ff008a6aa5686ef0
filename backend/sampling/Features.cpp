#include "sampling/Features.h"

#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

namespace ambler::sampling {

namespace {

// Gaussian smoothing that ignores missing pixels (normalised convolution):
// blur(v * valid) / blur(valid), NaN where nothing valid is near.
cv::Mat smoothValid(const cv::Mat& values, const cv::Mat& valid, double sigma) {
  cv::Mat masked = values.clone();
  masked.setTo(0.0f, ~valid);
  cv::Mat weight, sum;
  valid.convertTo(weight, CV_32F, 1.0 / 255.0);
  cv::GaussianBlur(masked, sum, cv::Size(), sigma);
  cv::GaussianBlur(weight, weight, cv::Size(), sigma);
  cv::Mat out = sum / weight;
  out.setTo(std::numeric_limits<float>::quiet_NaN(), weight < 1e-3f);
  return out;
}

cv::Mat rangeEdges(const sensor::StriperImage& image, const cv::Mat& valid,
                   const FeatureOptions& o) {
  cv::Mat r(image.rows(), image.cols(), CV_32F, 0.0f);
  const Eigen::Vector3d camera = image.camera.center();
  for (int i = 0; i < r.rows; ++i)
    for (int j = 0; j < r.cols; ++j)
      if (image.hasPoint(i, j)) r.at<float>(i, j) = float((image.point(i, j) - camera).norm());
  cv::Mat gx, gy, magnitude;
  cv::Sobel(r, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);  // range step per pixel [m]
  cv::Sobel(r, gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
  cv::magnitude(gx, gy, magnitude);
  // Only where the whole 3 x 3 neighbourhood was measured.
  cv::Mat inner;
  cv::erode(valid, inner, cv::Mat::ones(3, 3, CV_8U));
  magnitude.setTo(0.0f, ~inner);
  // The threshold follows the local distribution: r changes faster far
  // from the sensor, and a fixed threshold would find spurious edges there.
  const cv::Size window(o.window_px, o.window_px);
  cv::Mat weight, mean, mean_sq;
  inner.convertTo(weight, CV_32F, 1.0 / 255.0);
  cv::boxFilter(weight, weight, CV_32F, window);
  cv::boxFilter(magnitude, mean, CV_32F, window);
  cv::boxFilter(magnitude.mul(magnitude), mean_sq, CV_32F, window);
  weight = cv::max(weight, 1e-6f);
  mean /= weight;
  mean_sq /= weight;
  cv::Mat spread;
  cv::sqrt(cv::max(mean_sq - mean.mul(mean), 0.0f), spread);
  cv::Mat threshold = cv::max(mean + float(o.edge_sigmas) * spread, float(o.min_edge_m));
  cv::Mat edges = (magnitude > threshold) & inner;
  return edges;
}

cv::Mat normalEdges(const sensor::StriperImage& image, const cv::Mat& valid,
                    const FeatureOptions& o) {
  const int rows = image.rows(), cols = image.cols();
  auto plane = [&](const std::vector<float>& v) {
    return smoothValid(cv::Mat(rows, cols, CV_32F, const_cast<float*>(v.data())), valid,
                       o.smooth_px);
  };
  const cv::Mat x = plane(image.x), y = plane(image.y), z = plane(image.z);
  auto at = [&](int r, int c) {
    return Eigen::Vector3f(x.at<float>(r, c), y.at<float>(r, c), z.at<float>(r, c));
  };
  const Eigen::Vector3f camera = image.camera.center().cast<float>();
  cv::Mat n[3] = {cv::Mat(rows, cols, CV_32F, 0.0f), cv::Mat(rows, cols, CV_32F, 0.0f),
                  cv::Mat(rows, cols, CV_32F, 0.0f)};
  cv::Mat has_normal(rows, cols, CV_8U, cv::Scalar(0));
  for (int r = 1; r + 1 < rows; ++r)
    for (int c = 1; c + 1 < cols; ++c) {
      if (!valid.at<std::uint8_t>(r, c)) continue;
      const Eigen::Vector3f normal =
          (at(r, c + 1) - at(r, c - 1)).cross(at(r + 1, c) - at(r - 1, c));
      if (!normal.allFinite() || normal.norm() < 1e-12f) continue;
      // Facing the camera, so that concave and convex keep their meaning.
      const Eigen::Vector3f u =
          normal.normalized() * (normal.dot(camera - at(r, c)) < 0 ? -1.0f : 1.0f);
      for (int k = 0; k < 3; ++k) n[k].at<float>(r, c) = u[k];
      has_normal.at<std::uint8_t>(r, c) = 255;
    }
  for (auto& component : n) component = smoothValid(component, has_normal, o.smooth_px);
  auto unit = [&](int r, int c) {
    return Eigen::Vector3f(n[0].at<float>(r, c), n[1].at<float>(r, c), n[2].at<float>(r, c))
        .normalized();
  };
  // A crease between pixels step apart marks their midpoint. Only concave
  // ones (normals converging: an object resting on the terrain) count; a
  // rock's own convex edges would stop a contour inside it.
  const int step = o.normal_step_px, half = step / 2;
  cv::Mat edges(rows, cols, CV_8U, cv::Scalar(0));
  for (int r = 0; r + step < rows; ++r)
    for (int c = 0; c + step < cols; ++c) {
      if (!has_normal.at<std::uint8_t>(r, c)) continue;
      const Eigen::Vector3f here = unit(r, c);
      for (const auto& [dr, dc] : {std::pair{0, step}, std::pair{step, 0}}) {
        if (!has_normal.at<std::uint8_t>(r + dr, c + dc)) continue;
        const Eigen::Vector3f there = unit(r + dr, c + dc);
        const bool concave = (there - here).dot(at(r + dr, c + dc) - at(r, c)) < 0;
        if (concave && here.dot(there) < float(o.normal_dot_max))
          edges.at<std::uint8_t>(r + (dr ? half : 0), c + (dc ? half : 0)) = 255;
      }
    }
  return edges;
}

// Drops connected groups smaller than `min_px`.
void dropSpecks(cv::Mat& mask, int min_px) {
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8);
  for (int r = 0; r < mask.rows; ++r)
    for (int c = 0; c < mask.cols; ++c) {
      const int l = labels.at<int>(r, c);
      if (l > 0 && l < n && stats.at<int>(l, cv::CC_STAT_AREA) < min_px)
        mask.at<std::uint8_t>(r, c) = 0;
    }
}

}  // namespace

void validate(const FeatureOptions& o) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("feature option " + what);
  };
  require(o.window_px >= 3 && o.window_px <= 255 && o.window_px % 2 == 1,
          "window_px must be odd, in [3, 255]");
  require(o.edge_sigmas >= 0 && o.edge_sigmas <= 20, "edge_sigmas must be in [0, 20]");
  require(o.min_edge_m >= 0 && o.min_edge_m < 1, "min_edge_m must be in [0, 1) m");
  require(o.smooth_px > 0 && o.smooth_px <= 10, "smooth_px must be in (0, 10]");
  require(o.normal_dot_max > -1 && o.normal_dot_max < 1, "normal_dot_max must be in (-1, 1)");
  require(o.normal_step_px >= 1 && o.normal_step_px <= 10, "normal_step_px must be in [1, 10]");
  require(o.min_region_px >= 1, "min_region_px must be >= 1");
}

int FeatureMap::count(FeatureKind kind) const {
  int n = 0;
  for (auto k : kinds) n += (k & kind) != 0;
  return n;
}

FeatureMap extractFeatures(const sensor::StriperImage& image, const FeatureOptions& options) {
  validate(options);
  if (const auto problem = sensor::findProblem(image); !problem.empty())
    throw std::invalid_argument("striper image: " + problem);
  const int rows = image.rows(), cols = image.cols();
  cv::Mat valid(rows, cols, CV_8U, cv::Scalar(0));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      if (image.hasPoint(r, c)) valid.at<std::uint8_t>(r, c) = 255;
  cv::Mat range_edges = rangeEdges(image, valid, options);
  cv::Mat normal_edges = normalEdges(image, valid, options);
  dropSpecks(range_edges, options.min_region_px);
  dropSpecks(normal_edges, options.min_region_px);

  FeatureMap map;
  map.rows = rows, map.cols = cols;
  map.kinds.assign(std::size_t(rows) * cols, 0);
  cv::Mat any(rows, cols, CV_8U, cv::Scalar(0));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      std::uint8_t k = 0;
      if (!valid.at<std::uint8_t>(r, c)) k |= kShadow;
      if (range_edges.at<std::uint8_t>(r, c)) k |= kRangeEdge;
      if (normal_edges.at<std::uint8_t>(r, c)) k |= kNormalEdge;
      map.kinds[std::size_t(r) * cols + c] = k;
      if (k) any.at<std::uint8_t>(r, c) = 255;
    }
  cv::Mat labels;
  map.region_count = cv::connectedComponents(any, labels, 8, CV_32S) - 1;
  map.region.resize(map.kinds.size());
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) map.region[std::size_t(r) * cols + c] = labels.at<int>(r, c) - 1;
  return map;
}

}  // namespace ambler::sampling
