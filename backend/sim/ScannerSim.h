#pragma once

#include <cstdint>
#include <filesystem>

#include "io/Image.h"
#include "sensor/RangeImage.h"
#include "sim/RayCaster.h"

namespace ambler::sim {

// A laser rangefinder as configured in resources/config/scanner.json.
struct ScannerModel {
  sensor::ScanGeometry geometry;
  double range_sigma_k = 2e-4;        // sigma_rho = k rho^2 [1/m]
  double max_range = 40.0;            // [m]
  double mount_height = 5.0;          // sensor above the ground under the rover [m]
  double tilt = 30.0 * M_PI / 180.0;  // depression of the boresight [rad]

  // Sensor mount_height above `rover_ground_position`, tilted down by
  // `tilt`, boresight turned by `heading` counter-clockwise about +z
  // (heading 0 looks along +y).
  Eigen::Isometry3d mountPose(const Eigen::Vector3d& rover_ground_position,
                              double heading = 0.0) const;
};

// Reads a scanner model; throws io::FormatError naming the file and key.
ScannerModel readScannerModel(const std::filesystem::path& json_path);

// Ray-casts one range image from `sensor_to_world`. Pixels whose ray meets
// no ground within max_range get 0. Range noise N(0, k rho^2) is drawn from
// `noise_seed` (per row, so the result is the same at any thread count);
// k = 0 gives exact ranges.
sensor::RangeImage simulateScan(const RayCaster& caster, const ScannerModel& model,
                                const Eigen::Isometry3d& sensor_to_world, std::uint64_t noise_seed);

// Ground truth of a scan on a grid: exact terrain height at every cell
// centre and whether that ground point was seen. The state codes equal the
// map's (docs/formats.md): 0 visible (known), 1 outside the field of view
// or range (unknown), 2 inside it but occluded (shadow).
enum class Visibility : unsigned char { kVisible = 0, kOutsideView = 1, kOccluded = 2 };

struct VisibilityTruth {
  GridSpec grid;
  io::FloatImage height;  // [m], NaN off the terrain
  io::ByteImage state;    // Visibility codes
};

// Bounding box of where the image's edge rays meet the horizontal plane
// z = ground_z (rays that miss it are cut at max_range): the region a scan
// from this pose can cover.
Box2 groundFootprint(const ScannerModel& model, const Eigen::Isometry3d& sensor_to_world,
                     double ground_z);

// Truth by `caster`: for evaluations an EmbreeCaster, independent of the
// RayCaster that simulated the scan.
VisibilityTruth computeVisibility(const FirstHit& caster, const ScannerModel& model,
                                  const Eigen::Isometry3d& sensor_to_world, const GridSpec& grid);

}  // namespace ambler::sim
