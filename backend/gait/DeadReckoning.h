#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "gait/RoverModel.h"
#include "gait/Stance.h"

namespace ambler::gait {

// cmu-1990 'Real-time control': after a body move, the body pose is the
// rigid transform that maps the feet measured in the body frame (from the
// joint encoders) onto their stored world positions with the least squared
// error. The body stays level, so the transform is planar: a rotation about
// the vertical and a translation (Kabsch/Umeyama in 2-D).
struct DeadReckoningOptions {
  double slip_threshold_m = 0.03;  // residual above which a foot counts as slipped
};

struct DeadReckoningResult {
  BodyPose body;                  // link_z from the mean vertical offset
  std::vector<int> slipped_legs;  // feet left out of the final fit
  double rms_residual_m = 0.0;    // of the feet kept
  bool ok = false;                // at least three feet agree
};

// `feet_in_body` and `stored_world` per supporting leg (the same legs in
// the same order). A foot whose residual exceeds the threshold is dropped
// and the fit repeated, worst first, while three feet remain.
DeadReckoningResult deadReckon(const std::vector<int>& legs,
                               const std::vector<Eigen::Vector3d>& feet_in_body,
                               const std::vector<Eigen::Vector3d>& stored_world,
                               const DeadReckoningOptions& options = {});

// The rover's own pose estimate from its joint encoders alone, move by move
// (cmu-1990 'Real-time control'): a foot set down is stored where the
// encoders put it from the estimated body; after a body move the body is
// dead-reckoned from every foot, and a foot found slipped is stored again
// where it now is. It drifts with encoder noise, placement errors and
// slips; correcting it is the ground's work (scan registration).
class KinematicOdometry {
 public:
  KinematicOdometry(RoverModel model, Stance start, DeadReckoningOptions options = {})
      : model_(std::move(model)), estimate_(std::move(start)), options_(options) {}

  // A leg move ended (completed or stopped by a contact) with these readings.
  void legMoved(int leg, const LegJoints& joints);
  // A body move ended with these readings of every leg.
  DeadReckoningResult bodyMoved(const std::array<LegJoints, kLegCount>& joints);

  const Stance& estimate() const { return estimate_; }

 private:
  RoverModel model_;
  Stance estimate_;
  DeadReckoningOptions options_;
};

}  // namespace ambler::gait
