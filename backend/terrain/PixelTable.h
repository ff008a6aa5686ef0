#pragma once

#include <cmath>
#include <vector>

namespace ambler::terrain {

// A monotonic function of one variable tabulated at 4096 intervals and
// interpolated linearly: the inverse trigonometric functions that map a
// direction to an image row or column are the most expensive steps of
// following a locus. Empty (and unused) unless it matches the function to
// 1e-4 pixel everywhere.
class PixelTable {
 public:
  PixelTable() = default;
  template <typename F>
  PixelTable(double x_first, double x_last, F pixel_of) {
    const int intervals = 4096;
    first_ = x_first;
    step_ = (x_last - x_first) / intervals;
    inverse_step_ = 1.0 / step_;
    intervals_ = intervals;
    std::vector<double> values;
    for (int i = 0; i <= intervals; ++i) values.push_back(pixel_of(first_ + i * step_));
    for (int i = 0; i < intervals; ++i)
      if (!(std::abs(0.5 * (values[i] + values[i + 1]) - pixel_of(first_ + (i + 0.5) * step_)) <=
            1e-4))
        return;
    for (int i = 0; i < intervals; ++i)
      intervals_table_.push_back({values[i], values[i + 1] - values[i]});
  }
  bool empty() const { return intervals_table_.empty(); }
  // NaN outside the table.
  double operator()(double x) const {
    const double f = (x - first_) * inverse_step_;
    if (!(f >= 0 && f < intervals_)) return NAN;
    const int i = int(f);
    return intervals_table_[i].value + (f - i) * intervals_table_[i].rise;
  }
  // Beyond the table: extrapolated from the interval at the nearer end,
  // which is enough to say on which side of the table x is.
  double extrapolated(double x) const {
    const double f = (x - first_) * inverse_step_;
    const int i = f < 0 ? 0 : int(intervals_) - 1;
    return intervals_table_[i].value + (f - i) * intervals_table_[i].rise;
  }

 private:
  double first_ = 0.0, step_ = 0.0, inverse_step_ = 0.0, intervals_ = 0.0;
  // Per interval, the value at its start and the rise across it: one load
  // of 16 bytes and no subtraction on the way to a column.
  struct Interval {
    double value, rise;
  };
  std::vector<Interval> intervals_table_;
};

}  // namespace ambler::terrain
