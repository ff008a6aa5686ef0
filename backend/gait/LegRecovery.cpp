#include "gait/LegRecovery.h"

#include <algorithm>
#include <cmath>
#include <queue>

namespace ambler::gait {

namespace {

// The joint grid: rotation wraps around, extension spans the joint limits.
struct JointGrid {
  int n_rot = 0, n_ext = 0;
  double d_rot = 0.0, d_ext = 0.0, ext_min = 0.0;

  JointGrid(const RoverModel& m, const RecoveryOptions& o) {
    n_rot = std::max(8, int(std::lround(2 * M_PI / o.rotation_step_rad)));
    d_rot = 2 * M_PI / n_rot;
    ext_min = m.extension_min_m;
    n_ext = std::max(2, int(std::floor((m.extension_max_m - ext_min) / o.extension_step_m)) + 1);
    d_ext = (m.extension_max_m - ext_min) / (n_ext - 1);
  }
  int size() const { return n_rot * n_ext; }
  int index(int i, int j) const { return j * n_rot + i; }
  double rotation(int i) const { return i * d_rot; }
  double extension(int j) const { return ext_min + j * d_ext; }
  int nearest(const LegJoints& q) const {
    const int i = int(std::lround(std::remainder(q.rotation_rad, 2 * M_PI) / d_rot));
    const int j = std::clamp(int(std::lround((q.extension_m - ext_min) / d_ext)), 0, n_ext - 1);
    return index(((i % n_rot) + n_rot) % n_rot, j);
  }
};

double angleBetween(double a, double b) { return std::abs(std::remainder(a - b, 2 * M_PI)); }

// The sole height over each joint cell that clears the ground under the
// disk the sole sweeps between cells, INFINITY where the leg may not go
// (too high to lift over, another leg's vertical link, another shaft).
std::vector<double> soleHeightsNeeded(const RoverModel& model, const Stance& stance, int leg,
                                      const JointGrid& grid, const ClearanceField& clearance,
                                      const RecoveryOptions& o) {
  const double max_sole_z = stance.body.link_z - model.vertical_min_m;
  const double grown = 0.5 * model.foot_diameter_m + o.uncertainty_m +
                       0.5 * std::max(grid.d_rot * model.extension_max_m, grid.d_ext);
  std::vector<double> need(std::size_t(grid.size()));
  for (int j = 0; j < grid.n_ext; ++j)
    for (int i = 0; i < grid.n_rot; ++i) {
      const LegJoints q{grid.rotation(i), grid.extension(j), 0.0};
      const Eigen::Vector2d body = model.footInBody(leg, q).head<2>();
      double z = clearance(stance.body.toWorld(body), grown);
      z = std::isnan(z) ? max_sole_z : std::min(z + o.clearance_m, max_sole_z + 1e-9);
      if (z > max_sole_z) z = INFINITY;  // too high to lift over
      for (int other = 0; other < kLegCount; ++other) {
        if (other == leg || !stance.supporting[std::size_t(other)]) continue;
        const Eigen::Vector2d f =
            stance.body.toBody(Eigen::Vector2d(stance.feet[std::size_t(other)].head<2>()));
        if ((f - body).norm() < model.min_leg_separation_m) z = INFINITY;  // its vertical link
      }
      for (std::size_t s = 0; s < model.shafts.size(); ++s)
        if (int(s) != model.shaft_of_leg[std::size_t(leg)] &&
            (body - model.shafts[s]).norm() < model.shaft_clearance_m)
          z = INFINITY;
      need[std::size_t(grid.index(i, j))] = z;
    }
  return need;
}

// What a move between two neighbouring joint cells takes: its time (the
// slower of the horizontal joints, or the lift), its energy (the joints'
// power while they move, and the leg's weight lifted), and its cost, the
// time plus the energy weighed by the options' power-time ratio.
class MoveCost {
 public:
  MoveCost(const RoverModel& model, const JointGrid& grid, const std::vector<double>& need,
           const RecoveryOptions& o)
      : model_(model), grid_(grid), need_(need), o_(o) {}

  double lift_j_per_m() const { return o_.leg_mass_kg * o_.gravity_m_s2; }

  double operator()(int a, int b, double* time, double* energy) const {
    const int ia = a % grid_.n_rot, ja = a / grid_.n_rot, ib = b % grid_.n_rot,
              jb = b / grid_.n_rot;
    const double rot = angleBetween(grid_.rotation(ia), grid_.rotation(ib));
    const double ext = std::abs(grid_.extension(ja) - grid_.extension(jb));
    const double lift = std::max(0.0, need_[std::size_t(b)] - need_[std::size_t(a)]);
    const double horizontal =
        std::max(rot / model_.rotation_speed_rad_s, ext / model_.extension_speed_m_s);
    *time = std::max(horizontal, lift / model_.vertical_speed_m_s);
    *energy = model_.recovery_power_w * horizontal + lift_j_per_m() * lift;
    return *time + o_.power_time_ratio * *energy / model_.recovery_power_w;
  }

  // A lower bound of the cost from `a` to `target`: the horizontal joints'
  // time alone, with its energy.
  double toward(int a, int target) const {
    const double rot =
        angleBetween(grid_.rotation(a % grid_.n_rot), grid_.rotation(target % grid_.n_rot));
    const double ext =
        std::abs(grid_.extension(a / grid_.n_rot) - grid_.extension(target / grid_.n_rot));
    const double t = std::max(rot / model_.rotation_speed_rad_s, ext / model_.extension_speed_m_s);
    return t * (1.0 + o_.power_time_ratio);
  }

 private:
  const RoverModel& model_;
  const JointGrid& grid_;
  const std::vector<double>& need_;
  const RecoveryOptions& o_;
};

// A* over the joint grid (rotation wraps around) from `start` to `target`
// through cells with a finite sole height: the cells of the cheapest path,
// none when there is no path. `expanded` counts the cells expanded.
std::vector<int> cheapestPath(const JointGrid& grid, const std::vector<double>& need,
                              const MoveCost& cost_of, int start, int target, int& expanded) {
  std::vector<double> g(std::size_t(grid.size()), INFINITY);
  std::vector<int> parent(std::size_t(grid.size()), -1);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  g[std::size_t(start)] = 0.0;
  open.push({cost_of.toward(start, target), start});
  while (!open.empty()) {
    const auto [f, a] = open.top();
    open.pop();
    if (f > g[std::size_t(a)] + cost_of.toward(a, target) + 1e-9) continue;  // stale entry
    ++expanded;
    if (a == target) break;
    const int ia = a % grid.n_rot, ja = a / grid.n_rot;
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj) {
        const int jb = ja + dj;
        if ((di == 0 && dj == 0) || jb < 0 || jb >= grid.n_ext) continue;
        const int b = grid.index((ia + di + grid.n_rot) % grid.n_rot, jb);
        if (std::isinf(need[std::size_t(b)])) continue;
        double t, e;
        const double cost = g[std::size_t(a)] + cost_of(a, b, &t, &e);
        if (cost < g[std::size_t(b)]) {
          g[std::size_t(b)] = cost;
          parent[std::size_t(b)] = a;
          open.push({cost + cost_of.toward(b, target), b});
        }
      }
  }
  std::vector<int> cells;
  if (std::isinf(g[std::size_t(target)])) return cells;
  for (int c = target; c != -1; c = parent[std::size_t(c)]) cells.push_back(c);
  std::reverse(cells.begin(), cells.end());
  return cells;
}

}  // namespace

LegJoints liftOff(const LegJoints& standing, double vertical_m, const RoverModel& model) {
  return {standing.rotation_rad,
          std::clamp(standing.extension_m, model.extension_min_m, model.extension_max_m),
          vertical_m};
}

RecoveryPlan planLegRecovery(const RoverModel& model, const Stance& stance, int leg,
                             const Eigen::Vector3d& goal, const ClearanceField& clearance,
                             const RecoveryOptions& o, double touchdown_overshoot) {
  RecoveryPlan plan;
  const JointGrid grid(model, o);
  auto need = soleHeightsNeeded(model, stance, leg, grid, clearance, o);
  const LegJoints start_q = stance.joints(model, leg);
  const LegJoints goal_q = model.jointsFor(leg, stance.body.toBody(goal));
  const int start = grid.nearest(start_q), target = grid.nearest(goal_q);
  const double start_z = stance.feet[std::size_t(leg)].z();
  // Start and goal cells are where the foot is and will be: never blocked
  // by the foot's own ground, only lifted to what the neighbours need.
  for (int c : {start, target})
    if (std::isinf(need[std::size_t(c)]))
      need[std::size_t(c)] = stance.body.link_z - model.vertical_min_m;
  const MoveCost cost_of(model, grid, need, o);
  const auto cells = cheapestPath(grid, need, cost_of, start, target, plan.expanded);
  if (cells.empty()) return plan;

  // The sole height over a cell covers its neighbours on the path, so the
  // straight joint-space segments between waypoints stay clear.
  auto soleAt = [&](std::size_t k) {
    double z = need[std::size_t(cells[k])];
    if (k > 0) z = std::max(z, need[std::size_t(cells[k - 1])]);
    if (k + 1 < cells.size()) z = std::max(z, need[std::size_t(cells[k + 1])]);
    return z;
  };
  const double first = std::max({soleAt(0), start_z + o.clearance_m});
  plan.waypoints.push_back(liftOff(start_q, stance.body.link_z - first, model));
  double time = 0.0, energy = 0.0;
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const int c = cells[k];
    plan.waypoints.push_back({grid.rotation(c % grid.n_rot), grid.extension(c / grid.n_rot),
                              stance.body.link_z - std::max(soleAt(k), start_z + o.clearance_m)});
    if (k > 0) {
      double t, e;
      cost_of(cells[k - 1], c, &t, &e);
      time += t;
      energy += e;
    }
  }
  const double above_goal = std::max(soleAt(cells.size() - 1), goal.z() + o.clearance_m);
  plan.waypoints.push_back(
      {goal_q.rotation_rad, goal_q.extension_m, stance.body.link_z - above_goal});
  // A goal near the bottom of the leg's travel leaves less room to aim
  // below it than the overshoot; the aim stops at the limit.
  plan.waypoints.push_back(
      {goal_q.rotation_rad, goal_q.extension_m,
       std::min(stance.body.link_z - goal.z() + touchdown_overshoot, model.vertical_max_m)});
  for (const auto& q : plan.waypoints)
    plan.max_lift_m = std::max(plan.max_lift_m, stance.body.link_z - q.vertical_m - start_z);
  const double lift = first - start_z;
  plan.time_s = time + lift / model.vertical_speed_m_s;
  plan.energy_j = energy + cost_of.lift_j_per_m() * lift;
  plan.found = true;
  return plan;
}

std::vector<Eigen::Vector3d> footPath(const RoverModel& model, const Stance& stance, int leg,
                                      const RecoveryPlan& plan, const Eigen::Vector3d& goal,
                                      int samples_per_segment) {
  std::vector<Eigen::Vector3d> path{stance.feet[std::size_t(leg)]};
  LegJoints from = stance.joints(model, leg);
  for (std::size_t w = 0; w < plan.waypoints.size(); ++w) {
    const LegJoints& to = plan.waypoints[w];
    const bool last = w + 1 == plan.waypoints.size();
    // The controller turns the short way round (sim/RoverSim.cpp does too).
    const double turn = std::remainder(to.rotation_rad - from.rotation_rad, 2 * M_PI);
    for (int k = 1; k <= samples_per_segment; ++k) {
      const double t = double(k) / samples_per_segment;
      const LegJoints q{from.rotation_rad + t * turn,
                        from.extension_m + t * (to.extension_m - from.extension_m),
                        from.vertical_m + t * (to.vertical_m - from.vertical_m)};
      const Eigen::Vector3d foot = stance.body.toWorld(model.footInBody(leg, q));
      if (last && foot.z() <= goal.z()) {  // the contact stop
        path.push_back(goal);
        return path;
      }
      path.push_back(foot);
    }
    from = to;
  }
  return path;
}

}  // namespace ambler::gait
