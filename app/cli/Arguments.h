#pragma once

#include <Eigen/Geometry>
#include <chrono>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/GridSpec.h"

namespace ambler::cli {

// `count` comma-separated finite numbers; throws std::invalid_argument
// naming `what` and the expected `form` otherwise.
std::vector<double> parseNumbers(const std::string& text, std::size_t count,
                                 const std::string& what, const std::string& form);

// "XMIN,YMIN,XMAX,YMAX" [m]; throws std::invalid_argument naming the problem.
Box2 parseRegion(const std::string& text);

// Throws std::invalid_argument naming `what` when `degrees` is beyond a
// full turn either way (1e30 deg is a typing error, not a heading).
void requireTurn(double degrees, const std::string& what);

struct RoverAt {
  Eigen::Vector2d xy;
  double heading_deg = 0.0;  // 0: +y
};

// "X,Y,HEADING_DEG" ([m], [deg] within +-360); throws std::invalid_argument
// naming the problem.
RoverAt parseRoverAt(const std::string& text);

// The grid of `resolution` cells over `region`, at most 5e7 cells (a map of
// several layers then takes a few GB); throws std::invalid_argument naming
// `what` and its size otherwise.
GridSpec gridOver(const Box2& region, double resolution, const std::string& what);

inline double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// {"median", "p90", "max"} of the values; null when there are none.
nlohmann::json distribution(std::vector<double> values);

// Prints `value` as one JSON document on stdout.
void printJson(const nlohmann::json& value);

// A rigid motion as its 4 x 4 matrix, row by row.
nlohmann::json matrixJson(const Eigen::Isometry3d& motion);

// One line on stderr that a long command rewrites as it goes ("eval
// elevation: 7 of 72, rocks seed 1002 ..."), cleared at the end. Only on a
// terminal: scripts and tests read the two streams together, and `eval
// all` prints its own progress around each evaluation (Quiet).
class ProgressLine {
 public:
  ProgressLine(std::string what, std::size_t total);
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;
  void next(const std::string& item);

  // While one lives, no progress line is shown.
  struct Quiet {
    Quiet();
    ~Quiet();
  };

 private:
  std::string what_;
  std::size_t total_ = 0, done_ = 0;
  bool shown_ = false;
};

}  // namespace ambler::cli
