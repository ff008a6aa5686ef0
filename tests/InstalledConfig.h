#pragma once

// The configuration the tests walk with: the installed rover, footfall and
// scanner files, read once per test program.
#include "gait/RoverConfig.h"
#include "rover/SimulatedRover.h"

namespace ambler::testing_config {

inline const gait::GaitContext& ground() {
  static const gait::GaitContext c = gait::readInstalledGaitContext();
  return c;
}

inline const rover::SimulatedRoverConfig& simulator() {
  static const rover::SimulatedRoverConfig c = rover::readInstalledSimulatedRoverConfig();
  return c;
}

}  // namespace ambler::testing_config
