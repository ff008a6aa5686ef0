#include "sim/RoverSim.h"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <string>

#include "gait/GaitPlanner.h"
#include "io/Json.h"

namespace ambler::sim {

std::array<gait::LegJoints, gait::kLegCount> jointsOf(
    const std::array<LegState, gait::kLegCount>& legs) {
  std::array<gait::LegJoints, gait::kLegCount> out;
  for (std::size_t i = 0; i < legs.size(); ++i) out[i] = legs[i].joints;
  return out;
}

namespace {

// Highest ground under a foot disk, from its centre and two rings.
double groundUnderFoot(const Terrain& terrain, const Eigen::Vector2d& xy, double radius) {
  double top = terrain.height(xy.x(), xy.y());
  for (double ring : {0.5 * radius, radius})
    for (int k = 0; k < 12; ++k) {
      const double a = k * M_PI / 6;
      top = std::max(top, terrain.height(xy.x() + ring * std::cos(a), xy.y() + ring * std::sin(a)));
    }
  return top;
}

}  // namespace

ExecutionNoise readExecutionNoise(const std::filesystem::path& path) {
  const auto json = io::readJsonFile(path);
  const std::string context = "rover configuration '" + path.string() + "'";
  const io::JsonFields root(json, context);
  ExecutionNoise n;
  if (!root.has("simulation")) return n;
  const auto f = root.object("simulation");
  const struct {
    const char* key;
    double* value;
    double max;
  } numbers[] = {{"encoder_rotation_rad", &n.encoder_rotation_rad, 0.1},
                 {"encoder_extension_m", &n.encoder_extension_m, 0.5},
                 {"encoder_vertical_m", &n.encoder_vertical_m, 0.5},
                 {"placement_m", &n.placement_m, 0.5},
                 {"body_m", &n.body_m, 0.5},
                 {"body_rad", &n.body_rad, 0.5},
                 {"slip_probability", &n.slip_probability, 1.0},
                 {"slip_m", &n.slip_m, 1.0},
                 {"ground_creep_m", &n.ground_creep_m, 0.5},
                 {"ground_creep_rad", &n.ground_creep_rad, 0.5}};
  for (const auto& k : numbers) {
    if (!f.has(k.key)) continue;
    *k.value = f.number(k.key);
    if (*k.value < 0 || *k.value > k.max)
      f.fail(k.key, "must be in [0, " + std::to_string(k.max) + "]");
  }
  if (f.has("seed")) n.seed = std::uint64_t(f.integer("seed"));
  return n;
}

RoverSim::RoverSim(const Terrain& terrain, gait::RoverModel model, ExecutionNoise noise,
                   gait::Stance start)
    : terrain_(terrain), model_(std::move(model)), noise_(noise), truth_(start), rng_(noise.seed) {}

double RoverSim::soleClearanceNeeded(const Eigen::Vector2d& xy) const {
  return groundUnderFoot(terrain_, xy, 0.5 * model_.foot_diameter_m);
}

// A sole slides over the ground, so it cannot climb a wall: where the
// ground at `to` rises above it by more than the slide's length (steeper
// than 45 deg), the sole stays where it stood.
bool RoverSim::slideSole(Eigen::Vector3d& sole, const Eigen::Vector2d& to) const {
  const double ground = soleClearanceNeeded(to);
  if (ground - sole.z() > (to - sole.head<2>()).norm()) return false;
  sole << to, ground;
  return true;
}

void RoverSim::record(double* min_margin, int lifted) {
  SupportSample s{truth_.supportingFeet(lifted), truth_.centreOfGravity(model_)};
  const double m =
      gait::stabilityMargin(gait::conservativeSupportPolygon(s.feet), s.centre_of_gravity);
  *min_margin = std::min(*min_margin, m);
  trace_.push_back(std::move(s));
}

namespace {

void checkLegMove(const LegMove& move) {
  if (move.leg < 0 || move.leg >= gait::kLegCount)
    throw std::invalid_argument("leg move: leg " + std::to_string(move.leg) + " is not 0-5");
  if (move.waypoints.empty()) throw std::invalid_argument("leg move: no waypoints");
  for (const auto& w : move.waypoints)
    if (!std::isfinite(w.rotation_rad) || !std::isfinite(w.extension_m) ||
        !std::isfinite(w.vertical_m))
      throw std::invalid_argument("leg move: waypoint is not finite");
}

}  // namespace

Eigen::Vector3d RoverSim::footAt(int leg, const gait::LegJoints& joints) const {
  return truth_.body.toWorld(model_.footInBody(leg, joints));
}

bool RoverSim::nearASupportingFoot(const Eigen::Vector3d& foot) const {
  for (int i = 0; i < gait::kLegCount; ++i)
    if (truth_.supporting[std::size_t(i)] &&
        (truth_.feet[std::size_t(i)] - foot).head<2>().norm() < model_.foot_diameter_m)
      return true;
  return false;
}

// Moves the lifted leg from `q` towards `target` (clamped to the joint
// limits) in steps of at most 2 cm of travel, until it gets there or its
// sole meets the ground: a touch-down on the last segment, an unexpected
// contact before it. Returns whether it met the ground; `q` is where it
// stopped.
bool RoverSim::followSegment(int leg, gait::LegJoints& q, gait::LegJoints target, bool touch_down,
                             MoveReport& report) const {
  if (!model_.withinLimits(target)) report.event = "kinematic limit";
  target.extension_m =
      std::clamp(target.extension_m, model_.extension_min_m, model_.extension_max_m);
  target.vertical_m = std::clamp(target.vertical_m, model_.vertical_min_m, model_.vertical_max_m);
  const double d_rot = std::remainder(target.rotation_rad - q.rotation_rad, 2 * M_PI);
  const double d_ext = target.extension_m - q.extension_m,
               d_vert = target.vertical_m - q.vertical_m;
  const double seg_time = model_.legSegmentS(q, target);
  const double travel =
      std::max({std::abs(d_rot) * model_.extension_max_m, std::abs(d_ext), std::abs(d_vert)});
  const int n = std::max(1, int(std::ceil(travel / 0.02)));
  bool hit_leg = false;
  for (int s = 1; s <= n; ++s) {
    const double t = double(s) / n;
    const gait::LegJoints qs{q.rotation_rad + t * d_rot, q.extension_m + t * d_ext,
                             q.vertical_m + t * d_vert};
    const Eigen::Vector3d foot = footAt(leg, qs);
    const double ground = soleClearanceNeeded(foot.head<2>());
    if (!hit_leg && nearASupportingFoot(foot)) {
      hit_leg = true;
      ++report.collisions;
    }
    if (foot.z() < ground - 1e-3) {
      if (!touch_down) {
        ++report.collisions;
        report.event = "unexpected contact";
        report.completed = false;
      } else {
        report.event = "touch-down";
      }
      report.duration_s += seg_time * t;
      q = qs;
      return true;
    }
  }
  q = target;
  report.duration_s += seg_time;
  return false;
}

MoveReport RoverSim::executeLeg(const LegMove& move) {
  checkLegMove(move);
  MoveReport report;
  const auto leg = std::size_t(move.leg);
  truth_.supporting[leg] = false;
  record(&report.min_csp_margin_m);
  gait::LegJoints q = truth_.joints(model_, move.leg);
  // The final segment is the touch-down: contact there ends the move.
  bool touched = false;
  for (std::size_t k = 0; k < move.waypoints.size() && !touched; ++k)
    touched = followSegment(move.leg, q, move.waypoints[k], k + 1 == move.waypoints.size(), report);
  // Land where the leg stopped (the controller lowers it to contact), off
  // by the tracking error.
  std::normal_distribution<double> err(0.0, noise_.placement_m);
  Eigen::Vector3d foot = footAt(move.leg, q);
  foot.x() += err(rng_);
  foot.y() += err(rng_);
  foot.z() = soleClearanceNeeded(foot.head<2>());
  if (!touched)
    report.duration_s +=
        std::max(0.0, footAt(move.leg, q).z() - foot.z()) / model_.vertical_speed_m_s;
  truth_.feet[leg] = foot;
  truth_.supporting[leg] = true;
  if (!model_.withinLimits(truth_.joints(model_, move.leg))) report.event = "kinematic limit";
  return report;
}

void RoverSim::creep(double distance_m) {
  if (noise_.ground_creep_m == 0.0 && noise_.ground_creep_rad == 0.0) return;
  std::normal_distribution<double> unit(0.0, 1.0);
  const Eigen::Vector2d shift =
      noise_.ground_creep_m * distance_m * Eigen::Vector2d(unit(rng_), unit(rng_));
  const double twist = noise_.ground_creep_rad * distance_m * unit(rng_);
  const Eigen::Rotation2Dd turn(twist);
  const Eigen::Vector2d centre = truth_.body.xy;
  for (auto& foot : truth_.feet)
    (void)slideSole(foot, centre + shift + turn * (Eigen::Vector2d(foot.head<2>()) - centre));
  truth_.body.xy = centre + shift;
  truth_.body.heading_rad += twist;
}

MoveReport RoverSim::executeBody(const BodyMove& move) {
  if (!move.translation.allFinite() || !std::isfinite(move.rotation_rad) ||
      !std::isfinite(move.raise_m))
    throw std::invalid_argument("body move: not finite");
  MoveReport report;
  const gait::BodyPose start = truth_.body;
  const double distance = move.translation.norm(), turn = std::abs(move.rotation_rad);
  report.duration_s = model_.bodyMoveS(distance, turn, move.raise_m);
  std::normal_distribution<double> unit(0.0, 1.0);
  const double scale = noise_.body_m * std::max(distance, 0.1);
  const Eigen::Vector2d translation =
      move.translation + scale * Eigen::Vector2d(unit(rng_), unit(rng_));
  const double rotation = move.rotation_rad + noise_.body_rad * unit(rng_);
  const int n = std::max(2, int(std::ceil(distance / 0.02 + turn / 0.01)));
  for (int s = 1; s <= n; ++s) {
    const double t = double(s) / n;  // the profile changes timing, not the path
    truth_.body.xy = start.toWorld(Eigen::Vector2d(t * translation));
    truth_.body.heading_rad = start.heading_rad + t * rotation;
    truth_.body.link_z = start.link_z + t * move.raise_m;
    record(&report.min_csp_margin_m);
    for (int i = 0; i < gait::kLegCount; ++i)
      if (truth_.supporting[std::size_t(i)] && !model_.withinLimits(truth_.joints(model_, i)))
        report.event = "kinematic limit";
  }
  creep(distance);
  std::uniform_real_distribution<double> chance(0.0, 1.0), angle(0.0, 2 * M_PI);
  for (auto& foot : truth_.feet) {
    if (chance(rng_) >= noise_.slip_probability) continue;
    const double a = angle(rng_);
    if (slideSole(foot, foot.head<2>() + noise_.slip_m * Eigen::Vector2d(std::cos(a), std::sin(a))))
      ++slips_;
  }
  return report;
}

std::array<LegState, gait::kLegCount> RoverSim::legStates() {
  std::normal_distribution<double> unit(0.0, 1.0);
  std::array<LegState, gait::kLegCount> states;
  for (int i = 0; i < gait::kLegCount; ++i) {
    gait::LegJoints q = truth_.joints(model_, i);
    q.rotation_rad += noise_.encoder_rotation_rad * unit(rng_);
    q.extension_m += noise_.encoder_extension_m * unit(rng_);
    q.vertical_m += noise_.encoder_vertical_m * unit(rng_);
    states[std::size_t(i)] = {q, truth_.supporting[std::size_t(i)]};
  }
  const auto loads = footLoads(truth_, model_);
  for (int i = 0; i < gait::kLegCount; ++i) states[std::size_t(i)].force_n = loads[std::size_t(i)];
  return states;
}

std::array<double, gait::kLegCount> footLoads(const gait::Stance& stance,
                                              const gait::RoverModel& model) {
  constexpr double kGravity = 9.81;  // [m/s^2]: the Ambler walked on Earth test sites
  const Eigen::Vector2d cog = stance.centreOfGravity(model);
  std::vector<int> support;
  for (int i = 0; i < gait::kLegCount; ++i)
    if (stance.supporting[std::size_t(i)]) support.push_back(i);
  std::array<double, gait::kLegCount> loads{};
  if (support.empty()) return loads;
  // Force balance and the two moments about the centre of gravity.
  Eigen::MatrixXd a(3, Eigen::Index(support.size()));
  for (std::size_t k = 0; k < support.size(); ++k) {
    const Eigen::Vector2d r = stance.feet[std::size_t(support[k])].head<2>() - cog;
    a.col(Eigen::Index(k)) << 1.0, r.x(), r.y();
  }
  const Eigen::Vector3d b(model.mass_kg * kGravity, 0.0, 0.0);
  const Eigen::VectorXd f =
      a.transpose() * (a * a.transpose()).completeOrthogonalDecomposition().solve(b);
  for (std::size_t k = 0; k < support.size(); ++k)
    loads[std::size_t(support[k])] = std::max(0.0, f(Eigen::Index(k)));
  return loads;
}

gait::Stance settleOnTerrain(gait::Stance stance, const Terrain& terrain,
                             const gait::RoverModel& model) {
  for (int leg = 0; leg < gait::kLegCount; ++leg) {
    auto& foot = stance.feet[leg];
    foot.z() = groundUnderFoot(terrain, foot.head<2>(), 0.5 * model.foot_diameter_m);
    if (!std::isfinite(foot.z()))
      throw noGroundAtStart("foot " + std::to_string(leg), foot.head<2>(), terrain);
  }
  stance.body.link_z = gait::linkHeightFor(stance, model);
  return stance;
}

}  // namespace ambler::sim
