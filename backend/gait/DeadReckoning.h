#pragma once

#include <Eigen/Core>
#include <vector>

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

}  // namespace ambler::gait
