#pragma once

// The station's options as the widget tests use them: the installed
// configuration, operator "alice", logs in `log_dir`.
#include <QString>

#include "app/gs/GroundStation.h"
#include "core/Resources.h"
#include "gait/RoverConfig.h"

namespace ambler::gs::test {

inline StationOptions options(const QString& log_dir) {
  static const auto ground = gait::readInstalledGaitContext();
  static const auto simulator = rover::readInstalledSimulatedRoverConfig();
  static const auto scanner = sim::readScannerModel(findResource("config/scanner.json"));
  StationOptions o;
  o.operator_id = "alice";
  o.log_dir = log_dir;
  o.ground = ground;
  o.simulator = simulator;
  o.scanner = scanner;
  return o;
}

}  // namespace ambler::gs::test
