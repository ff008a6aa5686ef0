#include "gait/DeadReckoning.h"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

namespace ambler::gait {

namespace {

struct Fit {
  BodyPose body;
  std::vector<double> residuals;
};

Fit fitPlanar(const std::vector<Eigen::Vector3d>& body, const std::vector<Eigen::Vector3d>& world,
              const std::vector<bool>& keep) {
  std::vector<int> idx;
  for (std::size_t i = 0; i < body.size(); ++i)
    if (keep[i]) idx.push_back(int(i));
  Eigen::MatrixXd src(2, idx.size()), dst(2, idx.size());
  double dz = 0.0;
  for (std::size_t k = 0; k < idx.size(); ++k) {
    src.col(Eigen::Index(k)) = body[std::size_t(idx[k])].head<2>();
    dst.col(Eigen::Index(k)) = world[std::size_t(idx[k])].head<2>();
    dz += world[std::size_t(idx[k])].z() - body[std::size_t(idx[k])].z();
  }
  const Eigen::MatrixXd t = Eigen::umeyama(src, dst, false);  // rigid, no scale
  Fit fit;
  fit.body.xy = t.topRightCorner<2, 1>();
  fit.body.heading_rad = std::atan2(t(1, 0), t(0, 0));
  fit.body.link_z = dz / double(idx.size());
  for (std::size_t i = 0; i < body.size(); ++i)
    fit.residuals.push_back(
        (fit.body.toWorld(Eigen::Vector2d(body[i].head<2>())) - world[i].head<2>()).norm());
  return fit;
}

}  // namespace

DeadReckoningResult deadReckon(const std::vector<int>& legs,
                               const std::vector<Eigen::Vector3d>& feet_in_body,
                               const std::vector<Eigen::Vector3d>& stored_world,
                               const DeadReckoningOptions& options) {
  if (legs.size() != feet_in_body.size() || legs.size() != stored_world.size())
    throw std::invalid_argument("deadReckon: legs, body and world feet differ in count");
  DeadReckoningResult result;
  if (legs.size() < 3) return result;
  std::vector<bool> keep(legs.size(), true);
  std::size_t kept = legs.size();
  Fit fit = fitPlanar(feet_in_body, stored_world, keep);
  // Drop the worst foot while it is off by more than the threshold.
  while (true) {
    int worst = -1;
    for (std::size_t i = 0; i < legs.size(); ++i)
      if (keep[i] && fit.residuals[i] > options.slip_threshold_m &&
          (worst < 0 || fit.residuals[i] > fit.residuals[std::size_t(worst)]))
        worst = int(i);
    if (worst < 0 || kept <= 3) break;
    keep[std::size_t(worst)] = false;
    --kept;
    result.slipped_legs.push_back(legs[std::size_t(worst)]);
    fit = fitPlanar(feet_in_body, stored_world, keep);
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < legs.size(); ++i)
    if (keep[i]) sum += fit.residuals[i] * fit.residuals[i];
  result.body = fit.body;
  result.rms_residual_m = std::sqrt(sum / double(kept));
  result.ok = result.rms_residual_m <= options.slip_threshold_m;
  return result;
}

void KinematicOdometry::legMoved(int leg, const LegJoints& joints) {
  estimate_.feet.at(std::size_t(leg)) = estimate_.body.toWorld(model_.footInBody(leg, joints));
}

DeadReckoningResult KinematicOdometry::bodyMoved(const std::array<LegJoints, kLegCount>& joints) {
  std::vector<int> legs;
  std::vector<Eigen::Vector3d> body, world;
  for (int i = 0; i < kLegCount; ++i) {
    legs.push_back(i);
    body.push_back(model_.footInBody(i, joints[std::size_t(i)]));
    world.push_back(estimate_.feet[std::size_t(i)]);
  }
  const DeadReckoningResult dr = deadReckon(legs, body, world, options_);
  estimate_.body = dr.body;
  for (int leg : dr.slipped_legs)
    estimate_.feet[std::size_t(leg)] = estimate_.body.toWorld(body[std::size_t(leg)]);
  return dr;
}

}  // namespace ambler::gait
