#pragma once

// A simulated scan of the obstacle course with its true pose, for the
// registration and localization tests.
#include "core/Resources.h"
#include "mapping/Registration.h"
#include "sim/CourseScene.h"

namespace ambler::mapping::test {

struct View {
  Cloud points;  // in the sensor's frame
  Eigen::Isometry3d pose;
};

// Course `seed` scanned from the rover at `xy` facing `heading` [rad].
inline View viewFrom(std::uint64_t seed, const Eigen::Vector2d& xy, double heading) {
  const sim::CourseScene scene(seed, sim::readScannerModel(findResource("config/scanner.json")), xy,
                               heading);
  const auto image = scene.scan(seed);
  return {image.pointsInSensor(), image.sensor_to_world};
}

}  // namespace ambler::mapping::test
