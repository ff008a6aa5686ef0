#pragma once

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>

#include "core/GridSpec.h"

namespace ambler::cli {

// "XMIN,YMIN,XMAX,YMAX" [m]; throws std::invalid_argument naming the problem.
Box2 parseRegion(const std::string& text);

inline double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// Prints `value` as one JSON document on stdout.
void printJson(const nlohmann::json& value);

}  // namespace ambler::cli
