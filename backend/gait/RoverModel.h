#pragma once

#include <Eigen/Core>
#include <array>
#include <filesystem>

namespace ambler::gait {

constexpr int kLegCount = 6;

// One leg's joints (cmu-1990 'Walking robot with a circulating gait' §3):
// a rotational link about the stack's shaft, an extensional link in the
// horizontal plane, and a vertical link down to the foot.
struct LegJoints {
  double rotation_rad = 0.0;  // about +z, 0 along the body's +x (right)
  double extension_m = 1.5;   // shaft axis to the vertical link, horizontally
  double vertical_m = 2.0;    // link plane down to the sole of the foot
};

// The Ambler as resources/config/rover.json describes it. Body frame: x to
// the right, y forward, z up, origin on the body's vertical axis at the
// height of the horizontal links ("link plane"). Figures the report gives
// and those assumed are marked in that file and in docs/gait.md.
struct RoverModel {
  std::array<Eigen::Vector2d, 2> shafts{Eigen::Vector2d(-1.0, 0.0), Eigen::Vector2d(1.0, 0.0)};
  std::array<int, kLegCount> shaft_of_leg{0, 0, 0, 1, 1, 1};  // legs 0-2 left, 3-5 right
  double extension_min_m = 0.5;
  double extension_max_m = 2.5;
  double vertical_min_m = 0.3;
  double vertical_max_m = 3.0;
  double foot_diameter_m = 0.30;
  double link_plane_nominal_m = 2.4;  // above the supporting feet, on average
  double mass_kg = 3180.0;
  Eigen::Vector2d centre_of_gravity{0.0, 0.0};  // body frame [m]
  Eigen::Vector2d body_keepout_half{1.3, 1.0};  // no supporting foot under the body [m]
  double shaft_clearance_m = 0.45;              // vertical link to a shaft's axis
  double min_leg_separation_m = 0.6;            // between two vertical links
  double rotation_speed_rad_s = 0.15;
  double extension_speed_m_s = 0.15;
  double vertical_speed_m_s = 0.15;
  double body_speed_m_s = 2.0 / 60.0;  // cmu-1990 Table 1: propulsion power quoted at 2 m/min
  double body_turn_speed_rad_s = 0.02;
  double body_accel_m_s2 = 0.01;
  double recovery_power_w = 150.0;    // cmu-1990 Table 1
  double propulsion_power_w = 650.0;  // cmu-1990 Table 1

  const Eigen::Vector2d& shaftOf(int leg) const {
    return shafts[std::size_t(shaft_of_leg[std::size_t(leg)])];
  }
  // Foot sole in the body frame.
  Eigen::Vector3d footInBody(int leg, const LegJoints& q) const;
  // The joints that put leg's foot sole at `foot` (body frame); the rotation
  // is in (-pi, pi].
  LegJoints jointsFor(int leg, const Eigen::Vector3d& foot) const;
  bool withinLimits(const LegJoints& q) const;
  // How far q's extension and vertical reach lie outside their limits,
  // summed (0 within them).
  double beyondLimits(const LegJoints& q) const;
  // Seconds for a leg to go from `from` to `to`, each joint at its speed
  // (the slowest sets the time).
  double legSegmentS(const LegJoints& from, const LegJoints& to) const;
  // Seconds for a body move: translation and turn each on a trapezoidal
  // velocity profile, the link plane raised at the vertical speed.
  double bodyMoveS(double distance_m, double turn_rad, double raise_m) const;
};

// Throws std::invalid_argument naming the first field out of range.
void validate(const RoverModel& model);

// Reads the rover section of a rover.json; missing keys keep the defaults,
// a malformed file or an out-of-range value throws io::FormatError naming
// the file and the key.
RoverModel readRoverModel(const std::filesystem::path& path);

}  // namespace ambler::gait
