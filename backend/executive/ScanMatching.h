#pragma once

// The ground's correction of the rover's dead reckoning: each new scan is
// matched against the traverse map built so far (cmu-1990: iconic matching
// of terrain maps 'to augment dead-reckoning'), and the result becomes the
// correction from the frame the rover believes it is in to the map's. The
// inclinometers are trusted, so the match has four degrees of freedom: a
// shift, a turn about the vertical and a height offset, found by
// Gauss-Newton on the scan's points against the map's heights, each
// weighted by the map's sigma and the scanner's range noise.

#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "gait/Stance.h"
#include "sensor/RangeImage.h"
#include "terrain/ElevationMap.h"

namespace ambler::executive {

// A rigid motion of the ground plane (a turn about the world's vertical
// axis, then a shift) and a vertical offset: rover frame -> map frame.
struct PoseCorrection {
  Eigen::Vector2d shift{0.0, 0.0};
  double yaw_rad = 0.0;
  double dz_m = 0.0;

  Eigen::Isometry3d transform() const;
  PoseCorrection inverse() const;
  // This correction after `first`: (a * b).apply(x) == a.apply(b.apply(x)).
  PoseCorrection operator*(const PoseCorrection& first) const;
  gait::BodyPose apply(gait::BodyPose body) const;
  gait::Stance apply(gait::Stance stance) const;
};

struct ScanMatchOptions {
  int max_iterations = 20;
  double min_step_m = 1e-4;  // a step moving the scanner and its farthest point less ends it
  // A point counts when the map has heights (known or oblique) for the four
  // cells around it.
  int min_points = 1500;
  double point_sigma_floor_m = 0.005;  // added to the scanner's k r^2
  double robust_k = 3.0;               // residuals beyond k sigma are down-weighted (Huber)
  // Ground steeper than this (a gradient; 0.3 is 17 deg), in the map or in
  // the scan itself, is left out: a rock's faces and the shadow edges behind
  // them are where the map, built from other viewpoints, differs from the
  // new view, and a vertical residual there pulls the scan sideways. The
  // map's cells alone miss a small rock's faces (they round it off); the
  // scan, sampling only the faces it sees, then pulls towards the rocks, so
  // its returns next to a steep one along the line of sight go too.
  double max_slope = 0.3;
  double max_rms_m = 0.05;  // of the residuals the match ended with
  // The match's own standard deviations (from the normal equations): ground
  // that does not hold the scan in place leaves them large. Below these the
  // corrector weighs a match by them: sparse rocks hold the yaw to 1-2 mrad,
  // which refused at 1 mrad left dead reckoning's heading to carry on for
  // most of some walks.
  double max_sigma_xy_m = 0.01;
  double max_sigma_yaw_rad = 0.003;
};

// Throws std::invalid_argument naming the first option out of range.
void validate(const ScanMatchOptions& options);

// A move of the scan: (dx, dy, dyaw, dz), the turn about the vertical
// through the scanner.
using ScanOffset = Eigen::Matrix<double, 4, 1>;
using ScanOffsetCovariance = Eigen::Matrix<double, 4, 4>;

struct ScanMatch {
  PoseCorrection correction;  // to use from this scan on (the prior when refused)
  bool accepted = false;
  std::string refused;  // why, when not accepted
  int points = 0;       // scan points over known map
  int iterations = 0;
  double rms_m = 0.0;
  ScanOffset offset = ScanOffset::Zero();  // where the map puts the scan, from the prior
  ScanOffsetCovariance covariance = ScanOffsetCovariance::Zero();
  double sigma_xy_m = 0.0;  // along the worst horizontal direction
  double sigma_yaw_rad = 0.0;
  double chi2 = 0.0;       // the offset against dead reckoning's uncertainty (PoseCorrector)
  bool disputed = false;   // refused as disagreeing with dead reckoning
  bool relocated = false;  // accepted against dead reckoning: the matches agreed
  double change_m = 0.0;   // of the correction at the scanner
  double change_rad = 0.0;
  double ms = 0.0;
};

// Matches `scan` (placed by the rover's dead reckoning) against `map`,
// starting from `prior`; an accepted match's correction moves the scan all
// the way to `offset`. Never throws for a scan or map it cannot use: the
// match is refused with the reason.
ScanMatch matchScanToMap(const sensor::RangeImage& scan, const terrain::ElevationMap& map,
                         const PoseCorrection& prior, const ScanMatchOptions& options = {});

// How far the rover's dead reckoning wanders, as a random walk: the
// standard deviation after one metre of travel, growing with the root of
// the distance (cmu-1990: 1-2 cm per move of about half a metre).
struct DeadReckoningDrift {
  double position_m = 0.02;
  double heading_rad = 0.0015;
  double height_m = 0.01;
};

struct PoseCorrectorOptions {
  ScanMatchOptions match;
  DeadReckoningDrift drift;
  // The match's covariance comes from its own residuals, which leaves out
  // the map's errors that neighbouring cells share; it is widened by this.
  double match_sigma_scale = 3.0;
  // An offset beyond this chi-square (4 degrees of freedom; 18.5 is
  // p = 0.001) against dead reckoning and the match together is refused.
  double max_chi2 = 18.5;
  // Matches refused that way but agreeing with each other this many times
  // running mean that dead reckoning jumped (a slide no leg felt): the map
  // is believed and the rover relocated on it.
  int relocate_after = 3;
  double agree_m = 0.05;
  double agree_rad = 0.005;
};

// Fuses dead reckoning and scan matches into the correction in use: a
// Kalman filter over the correction, whose uncertainty grows as the rover
// walks and shrinks with each accepted match. A match is pulled towards
// dead reckoning by as much as it is less certain, so that ground which
// holds the scan only loosely cannot drag the map along with it.
class PoseCorrector {
 public:
  explicit PoseCorrector(PoseCorrectorOptions options = {});

  ScanMatch correct(const sensor::RangeImage& scan, const terrain::ElevationMap& map);
  const PoseCorrection& correction() const { return correction_; }
  const ScanOffsetCovariance& covariance() const { return covariance_; }

 private:
  ScanMatch commit(ScanMatch m, const sensor::RangeImage& scan, const ScanOffset& applied);

  PoseCorrectorOptions opt_;
  PoseCorrection correction_;
  ScanOffsetCovariance covariance_ = ScanOffsetCovariance::Zero();
  std::optional<Eigen::Vector2d> last_scanner_;  // in the rover's frame
  std::optional<ScanOffset> disputed_;           // the last refused offset
  int disputes_ = 0;                             // agreeing refusals running
};

}  // namespace ambler::executive
