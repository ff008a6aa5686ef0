#include "vision/DangerMap.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/Angles.h"

namespace ambler::vision {

namespace {

// The lower edge of the view from the vertical [rad].
double lowerEdge(const CameraModel& c) { return (c.alpha_deg - 0.5 * c.beta_deg) * kDeg; }

// Window k's rows from the bottom, [begin, end) (eq. 2's two cases).
struct Rows {
  double begin, end;
};
Rows windowRows(const CameraModel& c, int k, double d) {
  const double end = rowAt(c, windowAngle(c, k, d));
  return {k < 2 ? 0.0 : rowAt(c, windowAngle(c, k - 2, d)), end};
}

double horizonRow(const CameraModel& c) {
  const double theta = 0.5 * M_PI - lowerEdge(c);  // the horizontal ray
  if (theta >= c.beta_deg * kDeg) return c.rows;   // above the top of the view
  return std::min(rowAt(c, theta), double(c.rows));
}

// The row where windows spanning `d` on the ground narrow to 2 pixels: the
// end of the last wider one.
int narrowingRow(const CameraModel& c, double d, double horizon) {
  double end = 0.0;
  for (int k = 0; k < 100000; ++k) {
    const Rows rows = windowRows(c, k, d);
    if (rows.end - rows.begin <= 2.0 || rows.end >= horizon) break;
    end = rows.end;
  }
  return int(std::lround(std::min(end, horizon)));
}

// Values added to rectangles of pixels in O(1) each, summed at the end
// (a 2-D difference array).
class RectangleSums {
 public:
  RectangleSums(int rows, int cols) : rows_(rows), cols_(cols), d_((rows + 1) * (cols + 1), 0.0) {}
  void add(int r0, int r1, int c0, int c1, double v) {  // rows [r0, r1), cols [c0, c1)
    at(r0, c0) += v, at(r0, c1) -= v, at(r1, c0) -= v, at(r1, c1) += v;
  }
  // Prefix sums: d_(r, c) becomes the total added over pixel (r, c).
  void finish() {
    for (int r = 0; r <= rows_; ++r)
      for (int c = 0; c <= cols_; ++c) {
        if (r > 0) at(r, c) += at(r - 1, c);
        if (c > 0) at(r, c) += at(r, c - 1);
        if (r > 0 && c > 0) at(r, c) -= at(r - 1, c - 1);
      }
  }
  double operator()(int r, int c) const { return d_[std::size_t(r) * (cols_ + 1) + c]; }

 private:
  double& at(int r, int c) { return d_[std::size_t(r) * (cols_ + 1) + c]; }
  int rows_, cols_;
  std::vector<double> d_;
};

// Sums of values and squares over rectangles in O(1) (integral images).
class Integral {
 public:
  explicit Integral(const io::FloatImage& image)
      : cols_(image.cols + 1), s_(std::size_t(image.rows + 1) * cols_, 0.0), s2_(s_.size(), 0.0) {
    for (int r = 0; r < image.rows; ++r)
      for (int c = 0; c < image.cols; ++c) {
        const double v = image(r, c);
        const auto k = std::size_t(r + 1) * cols_ + c + 1;
        s_[k] = v + s_[k - 1] + s_[k - cols_] - s_[k - cols_ - 1];
        s2_[k] = v * v + s2_[k - 1] + s2_[k - cols_] - s2_[k - cols_ - 1];
      }
  }
  // Mean and variance over rows [r0, r1), cols [c0, c1).
  std::pair<double, double> meanVariance(int r0, int r1, int c0, int c1) const {
    const double n = double(r1 - r0) * (c1 - c0);
    const double mean = box(s_, r0, r1, c0, c1) / n;
    return {mean, std::max(box(s2_, r0, r1, c0, c1) / n - mean * mean, 0.0)};
  }

 private:
  double box(const std::vector<double>& s, int r0, int r1, int c0, int c1) const {
    auto at = [&](int r, int c) { return s[std::size_t(r) * cols_ + c]; };
    return at(r1, c1) - at(r0, c1) - at(r1, c0) + at(r0, c0);
  }
  std::size_t cols_;
  std::vector<double> s_, s2_;
};

// Windows `width` pixels square over rows [y0, y1) from the bottom, at half
// a width apart across the image (the last one flush with the right edge);
// each adds its mean or variance to the pixels it covers.
void addWindows(const io::FloatImage& image, const Integral& integral, int y0, int y1, int width,
                bool variance, RectangleSums& sums, RectangleSums& counts) {
  const int r0 = image.rows - y1, r1 = image.rows - y0;  // stored rows, top down
  const int step = std::max(width / 2, 1);
  for (int c0 = 0;; c0 += step) {
    const int c1 = std::min(c0 + width, image.cols);
    const int left = c1 - std::min(width, image.cols);
    const auto [mean, var] = integral.meanVariance(r0, r1, left, c1);
    sums.add(r0, r1, left, c1, variance ? var : mean);
    counts.add(r0, r1, left, c1, 1.0);
    if (c1 == image.cols) break;
  }
}

// Every window of the band of `d` below `limit`; above the last one, up to
// `top`, 3-pixel windows when `fill` (the shades beyond y_g).
void addBand(const io::FloatImage& image, const Integral& integral, const CameraModel& c, double d,
             int limit, int top, bool variance, bool fill, RectangleSums& sums,
             RectangleSums& counts) {
  int covered = 0;
  for (int k = 0;; ++k) {
    const Rows rows = windowRows(c, k, d);
    const int y0 = int(std::floor(rows.begin)), y1 = int(std::lround(rows.end));
    if (y1 > limit || y1 - y0 <= 2) break;
    addWindows(image, integral, y0, y1, y1 - y0, variance, sums, counts);
    covered = y1;
  }
  if (!fill) return;
  for (int y0 = std::max(covered - 2, 0); y0 + 3 <= top; ++y0)
    addWindows(image, integral, y0, y0 + 3, 3, variance, sums, counts);
}

}  // namespace

void validate(const CameraModel& c) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("camera " + what);
  };
  require(c.rows >= 8 && c.rows <= 100000, "rows must be in [8, 100000]");
  require(c.beta_deg > 0 && c.beta_deg < 170, "beta_deg (field of view) must be in (0, 170)");
  require(c.alpha_deg - 0.5 * c.beta_deg > 0 && c.alpha_deg - 0.5 * c.beta_deg < 89,
          "alpha_deg - beta_deg / 2 (the lower edge of the view from the vertical) must be in "
          "(0, 89): the view must reach the ground ahead of the camera");
  require(c.height_m > 0 && c.height_m < 1000, "height_m must be in (0, 1000)");
  require(c.wheel_diameter_m > 0 && c.wheel_diameter_m < 100,
          "wheel_diameter_m must be in (0, 100)");
  require(c.rover_diagonal_m > 0 && c.rover_diagonal_m < 100,
          "rover_diagonal_m must be in (0, 100)");
}

double windowAngle(const CameraModel& c, int k, double d) {
  const double t = std::tan(lowerEdge(c)), s = (k + 1) * d;
  return std::atan(s / (2 * c.height_m + (s + 2 * c.height_m * t) * t));
}

double rowAt(const CameraModel& c, double theta) {
  const double t = std::tan(0.5 * c.beta_deg * kDeg), u = std::tan(theta);
  return c.rows * (1 + t * t) / (2 * t) * u / (1 + t * u);
}

double windowWidth(const CameraModel& c, int k, double d) {
  if (k < 2) return rowAt(c, windowAngle(c, k, d));
  const double half = 0.5 * c.beta_deg * kDeg;
  return c.rows / (2 * std::tan(half)) *
         (std::tan(half - windowAngle(c, k - 2, d)) - std::tan(half - windowAngle(c, k, d)));
}

Bands bandsOf(const CameraModel& c) {
  validate(c);
  const double horizon = horizonRow(c);
  Bands b;
  b.y_h = int(std::lround(horizon));
  b.y_g = narrowingRow(c, c.rover_diagonal_m, horizon);
  b.y_v = std::min(narrowingRow(c, c.wheel_diameter_m, horizon), b.y_g);
  return b;
}

io::FloatImage degreeOfDanger(const io::FloatImage& image, const CameraModel& c,
                              const DangerOptions& o) {
  validate(c);
  if (image.rows != c.rows)
    throw std::invalid_argument("danger: the image has " + std::to_string(image.rows) +
                                " rows, the camera model " + std::to_string(c.rows));
  if (!(o.variance_threshold > 0) || !(o.max_brightness > 0))
    throw std::invalid_argument("danger: B and N must be positive");
  const Bands bands = bandsOf(c);
  const Integral integral(image);
  RectangleSums g(image.rows, image.cols), g_count(image.rows, image.cols);
  RectangleSums v(image.rows, image.cols), v_count(image.rows, image.cols);
  addBand(image, integral, c, c.rover_diagonal_m, bands.y_h, bands.y_h, false, true, g, g_count);
  addBand(image, integral, c, c.wheel_diameter_m, bands.y_v, bands.y_v, true, false, v, v_count);
  for (auto* s : {&g, &g_count, &v, &v_count}) s->finish();
  io::FloatImage danger(image.rows, image.cols, NAN);
  for (int r = 0; r < image.rows; ++r) {
    const int y = image.rows - 1 - r;
    if (y >= bands.y_h) continue;
    for (int col = 0; col < image.cols; ++col) {
      const double count = g_count(r, col);
      const double shade = count > 0 ? g(r, col) / count : image(r, col);
      double f0 = 1.0;
      if (y < bands.y_v && v_count(r, col) > 0) {
        const double variance = v(r, col) / v_count(r, col);
        if (variance > o.variance_threshold) f0 = o.variance_threshold / variance;
      }
      danger(r, col) = float(std::clamp(1.0 - f0 * shade / o.max_brightness, 0.0, 1.0));
    }
  }
  return danger;
}

}  // namespace ambler::vision
