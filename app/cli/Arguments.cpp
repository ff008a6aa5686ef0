#include "cli/Arguments.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <unistd.h>

namespace ambler::cli {

std::vector<double> parseNumbers(const std::string& text, std::size_t count,
                                 const std::string& what, const std::string& form) {
  std::vector<double> v;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    std::size_t used = 0;
    double d = 0;
    try {
      d = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(d))
      throw std::invalid_argument(what + " '" + text + "': '" + item + "' is not a number");
    v.push_back(d);
  }
  if (v.size() != count) throw std::invalid_argument(what + " '" + text + "' must be " + form);
  return v;
}

Box2 parseRegion(const std::string& text) {
  const auto v = parseNumbers(text, 4, "region", "XMIN,YMIN,XMAX,YMAX");
  if (v[2] <= v[0] || v[3] <= v[1])
    throw std::invalid_argument("region '" + text + "' is empty: need XMIN < XMAX and YMIN < YMAX");
  return {v[0], v[1], v[2], v[3]};
}

void requireTurn(double degrees, const std::string& what) {
  if (std::abs(degrees) <= 360) return;
  char text[64];
  std::snprintf(text, sizeof text, " %g deg is outside -360..360", degrees);
  throw std::invalid_argument(what + text);
}

RoverAt parseRoverAt(const std::string& text) {
  const auto v = parseNumbers(text, 3, "--at", "X,Y,HEADING_DEG");
  requireTurn(v[2], "--at heading");
  return {{v[0], v[1]}, v[2]};
}

GridSpec gridOver(const Box2& region, double resolution, const std::string& what) {
  const auto grid = GridSpec::covering(region, resolution);
  if (grid.rows <= 0 || grid.cols <= 0) {
    std::ostringstream box;
    box << "x " << region.x_min << ".." << region.x_max << " m, y " << region.y_min << ".."
        << region.y_max << " m";
    throw std::invalid_argument(what + " covers no cells: its region (" + box.str() +
                                ") has no area; give a --region");
  }
  if (double(grid.rows) * grid.cols > 5e7)
    throw std::invalid_argument(what + " of " + std::to_string(grid.rows) + "x" +
                                std::to_string(grid.cols) +
                                " cells is too large; use a coarser --resolution or a smaller "
                                "--region");
  return grid;
}

void printJson(const nlohmann::json& value) { std::cout << value.dump(2) << std::endl; }

nlohmann::json matrixJson(const Eigen::Isometry3d& motion) {
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < 4; ++i)
    rows.push_back({motion(i, 0), motion(i, 1), motion(i, 2), motion(i, 3)});
  return rows;
}

nlohmann::json distribution(std::vector<double> values) {
  if (values.empty()) return nullptr;
  std::sort(values.begin(), values.end());
  const auto at = [&](double q) {
    return values[std::min(values.size() - 1, std::size_t(q * double(values.size())))];
  };
  return {{"median", at(0.5)}, {"p90", at(0.9)}, {"max", values.back()}};
}

namespace {
int quiet_depth = 0;
}

ProgressLine::Quiet::Quiet() { ++quiet_depth; }
ProgressLine::Quiet::~Quiet() { --quiet_depth; }

ProgressLine::ProgressLine(std::string what, std::size_t total)
    : what_(std::move(what)), total_(total), shown_(quiet_depth == 0 && isatty(STDERR_FILENO)) {}

ProgressLine::~ProgressLine() {
  if (shown_) std::cerr << "\r\033[K" << std::flush;
}

void ProgressLine::next(const std::string& item) {
  ++done_;
  if (shown_)
    std::cerr << "\r\033[K" << what_ << ": " << done_ << " of " << total_ << ", " << item << " ..."
              << std::flush;
}

}  // namespace ambler::cli
