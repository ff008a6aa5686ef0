#pragma once

// Pairs of simulated scans for measuring registration: two viewpoints on a
// terrain family, with the truth and a perturbed initial guess, each cloud
// levelled about its sensor (what the rover's inclinometers leave) and
// placed in the world by a known rigid motion.

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "sim/ScannerSim.h"
#include "sim/TerrainFamilies.h"

namespace ambler::sim {

struct ScanPairOptions {
  double min_distance_m = 1.0, max_distance_m = 5.0;     // between the two scanners
  double min_turn_deg = 5.0, max_turn_deg = 30.0;        // between their headings
  double max_error_m = 0.3, max_error_deg = 3.0;         // of the initial guess
  std::vector<double> noise_k{0.0, 2.5e-4, 5e-4, 1e-3};  // one drawn per pair [1/m]
  // The target scans another terrain of the family (seed + 500): the two
  // clouds do not overlap and a registration must say so.
  bool foreign = false;
};

struct ScanPair {
  TerrainFamily family = TerrainFamily::kCourse;
  std::uint64_t seed = 0;
  bool foreign = false;
  double distance_m = 0.0, turn_deg = 0.0, noise_k = 0.0;
  double error_m = 0.0, error_deg = 0.0;        // of the initial guess
  std::vector<Eigen::Vector3d> source, target;  // each in its levelled sensor frame
  Eigen::Isometry3d source_to_world = Eigen::Isometry3d::Identity();  // levelled frame -> world
  Eigen::Isometry3d target_to_world = Eigen::Isometry3d::Identity();
  // The guess's error, a motion of the source about its own levelled frame.
  Eigen::Isometry3d error = Eigen::Isometry3d::Identity();

  // Source -> target, and the guess, for the clouds as they are (levelled)...
  Eigen::Isometry3d levelledTruth() const { return target_to_world.inverse() * source_to_world; }
  Eigen::Isometry3d levelledGuess() const { return levelledTruth() * error; }
  // ...and for both clouds moved into the world frame.
  Eigen::Isometry3d worldGuess() const {
    return source_to_world * error * source_to_world.inverse();
  }
};

// The pair drawn from `seed` on `family` (deterministic).
ScanPair makeScanPair(TerrainFamily family, std::uint64_t seed, const ScannerModel& scanner,
                      const ScanPairOptions& options = {});

}  // namespace ambler::sim
