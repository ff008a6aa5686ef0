// `eval mapping`: registration of simulated scans from different
// viewpoints and global localization in a coarse model (bakambu-csa §2),
// against the simulator's poses. `register`: the same on PCD files. `mesh`
// and `path`: the triangulated terrain of a cloud and a path over it
// (§3-4).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <utility>

#include "cli/Arguments.h"
#include "cli/Commands.h"
#include "core/Resources.h"
#include "core/SideBySide.h"
#include "mapping/Localization.h"
#include "mapping/MappingFiles.h"
#include "mapping/Registration.h"
#include "mapping/TerrainPath.h"
#include "sim/CourseScene.h"

namespace ambler::cli {

namespace {

struct View {
  mapping::Cloud points;  // in the sensor's frame
  Eigen::Isometry3d pose;
};

View viewFrom(const sim::ScannerModel& model, std::uint64_t seed, const Eigen::Vector2d& xy,
              double heading) {
  const sim::CourseScene scene(seed, model, xy, heading);
  const auto image = scene.scan(seed * 7 + 1);
  return {image.pointsInSensor(), image.sensor_to_world};
}

double angleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180 / M_PI;
}

// The course as a 1 m model from orbital altimetry, over a square around
// the origin.
mapping::Cloud coarseModel(std::uint64_t seed, double half_size) {
  const sim::CourseScene scene(seed, sim::readScannerModel(findResource("config/scanner.json")));
  const auto grid = GridSpec::covering({-half_size, -half_size, half_size, half_size}, 1.0);
  return sim::orbitalModel(scene.terrain(), grid);
}

// The centre of the triangle nearest `xy` that is no steeper than the
// limit: a start or goal the planner accepts.
Eigen::Vector2d nearestCentre(const mapping::TerrainMesh& mesh, const Eigen::Vector2d& xy,
                              double max_slope_deg) {
  Eigen::Vector2d best = xy;
  double nearest = INFINITY;
  for (int t = 0; t < int(mesh.size()); ++t) {
    if (mesh.slopeRad(t) > max_slope_deg * M_PI / 180) continue;
    const Eigen::Vector2d c =
        (mesh.corner(t, 0) + mesh.corner(t, 1) + mesh.corner(t, 2)).head<2>() / 3;
    if (const double d = (c - xy).squaredNorm(); d < nearest) nearest = d, best = c;
  }
  return best;
}

struct EvalMappingArgs {
  std::vector<std::uint64_t> seeds{1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  bool json = true;  // the only output form
};

nlohmann::json evalMapping(const EvalMappingArgs& args) {
  const auto model = sim::readScannerModel(findResource("config/scanner.json"));
  std::vector<double> trans_pct, rot_deg, icp_ms, global_s, global_err_m, triangles, path_m,
      path_ms;
  int global_ok = 0, paths_found = 0;
  for (const auto seed : args.seeds) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    // A second view 1.5-3.5 m on, up to 0.5 m aside, turned up to 10 deg;
    // dead reckoning off by 10 % of the move and 2 degrees.
    // The first view anywhere within 5 m of the course's centre, at any
    // heading (global localization must find it in the coarse model).
    const Eigen::Vector2d at(5 * u(rng), 5 * u(rng));
    const double heading = M_PI * u(rng);
    const Eigen::Vector2d ahead(-std::sin(heading), std::cos(heading));
    const Eigen::Vector2d aside(ahead.y(), -ahead.x());
    const View a = viewFrom(model, seed, at, heading);
    const View b = viewFrom(model, seed, at + (2.5 + u(rng)) * ahead + 0.5 * u(rng) * aside,
                            heading + 10 * M_PI / 180 * u(rng));
    const Eigen::Isometry3d truth = a.pose.inverse() * b.pose;
    const double travelled = (b.pose.translation() - a.pose.translation()).norm();
    const Eigen::Vector3d drift = Eigen::Vector3d(u(rng), u(rng), 0.3 * u(rng)).normalized();
    const Eigen::Isometry3d dead_reckoned =
        Eigen::Translation3d(0.1 * travelled * drift) * truth *
        Eigen::AngleAxisd(2 * M_PI / 180, Eigen::Vector3d(u(rng), u(rng), 1).normalized());
    auto start = std::chrono::steady_clock::now();
    const auto r = mapping::registerClouds(b.points, a.points, dead_reckoned, {},
                                           {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});
    icp_ms.push_back(millisecondsSince(start));
    trans_pct.push_back(100 * (r.transform.translation() - truth.translation()).norm() / travelled);
    rot_deg.push_back(angleDeg(r.transform.linear(), truth.linear()));
    // Global: view a, without a prior, into the coarse model of the course.
    const auto coarse = coarseModel(seed, 30.0);
    start = std::chrono::steady_clock::now();
    const auto g = mapping::localize(a.points, mapping::withoutYaw(a.pose.linear()), coarse);
    global_s.push_back(millisecondsSince(start) / 1000);
    const double err = g ? (g->transform.translation() - a.pose.translation()).norm() : INFINITY;
    global_err_m.push_back(err);
    global_ok += g && err < 0.5 && angleDeg(g->transform.linear(), a.pose.linear()) < 2.0;
    // The mesh of view a in the world and a path across it, from the
    // triangles nearest 5 m and 16 m ahead (the view has holes: shadows).
    const auto mesh = mapping::triangulate(mapping::transformed(a.points, a.pose));
    triangles.push_back(double(mesh.size()));
    start = std::chrono::steady_clock::now();
    const double limit = mapping::PathOptions{}.max_slope_deg;
    const auto path = mapping::planPath(mesh, nearestCentre(mesh, at + 5 * ahead, limit),
                                        nearestCentre(mesh, at + 16 * ahead, limit));
    path_ms.push_back(millisecondsSince(start));
    if (path.found) ++paths_found, path_m.push_back(path.length_m);
  }
  return {{"cases", args.seeds.size()},
          {"icp_trans_err_pct_of_distance", distribution(trans_pct)},
          {"icp_rot_err_deg", distribution(rot_deg)},
          {"icp_ms", distribution(icp_ms)},
          {"global_loc_success_rate", double(global_ok) / double(args.seeds.size())},
          {"global_loc_success_rule", "within 0.5 m and 2 deg of the true pose"},
          {"global_loc_err_m", distribution(global_err_m)},
          {"global_loc_s", distribution(global_s)},
          {"mesh_triangles", distribution(triangles)},
          {"paths_found", paths_found},
          {"path_len_m", distribution(path_m)},
          {"path_ms", distribution(path_ms)}};
}

// USGS's DEM of the Jacksboro fault, Tennessee (3 arc-seconds, 344 x 403),
// as Debian's python-matplotlib-data ships it.
constexpr const char* kJacksboroDem =
    "/usr/share/matplotlib/mpl-data/sample_data/jacksboro_fault_dem.npz";

struct EvalDemArgs {
  std::string dem = kJacksboroDem;
  int windows = 10;
  double window_m = 5000.0;
  double cell_m = 400.0;  // patches of a quarter cell need a DEM point each
  double max_slope_deg = 20.0;
  std::uint64_t seed = 1;
  bool json = true;  // the only output form
};

// The cloud's mean height per square of `cell` metres, at the squares'
// centres: a coarse model such as orbital altimetry gives.
mapping::Cloud blockMeans(const mapping::Cloud& cloud, double cell) {
  std::map<std::pair<long, long>, std::pair<double, int>> sums;
  for (const auto& p : cloud) {
    auto& s = sums[{std::lround(std::floor(p.x() / cell)), std::lround(std::floor(p.y() / cell))}];
    s.first += p.z(), ++s.second;
  }
  mapping::Cloud model;
  for (const auto& [key, s] : sums)
    model.emplace_back((double(key.first) + 0.5) * cell, (double(key.second) + 0.5) * cell,
                       s.first / s.second);
  return model;
}

// The mapping module on real terrain: the DEM meshed, a path across it, and
// windows of it, turned and moved, found in its block-mean model.
nlohmann::json evalDem(const EvalDemArgs& args) {
  const auto cloud = mapping::readDem(args.dem);
  Eigen::Vector2d lo = cloud[0].head<2>(), hi = lo;
  for (const auto& p : cloud) lo = lo.cwiseMin(p.head<2>()), hi = hi.cwiseMax(p.head<2>());
  const double spacing = std::sqrt((hi - lo).prod() / double(cloud.size()));
  mapping::MeshOptions mesh_options;
  mesh_options.tolerance_m = 10.0;
  mesh_options.min_cell_m = 2 * spacing;
  mesh_options.max_cell_m = 64 * spacing;
  auto start = std::chrono::steady_clock::now();
  const auto mesh = mapping::triangulate(cloud, mesh_options);
  const double mesh_ms = millisecondsSince(start);

  mapping::PathOptions path_options;
  path_options.max_slope_deg = args.max_slope_deg;
  const Eigen::Vector2d margin = 0.15 * (hi - lo);
  start = std::chrono::steady_clock::now();
  const auto path =
      mapping::planPath(mesh, nearestCentre(mesh, lo + margin, args.max_slope_deg),
                        nearestCentre(mesh, hi - margin, args.max_slope_deg), path_options);
  const double path_ms = millisecondsSince(start);
  double steepest = 0.0;
  for (const int t : path.triangles) steepest = std::max(steepest, mesh.slopeRad(t) * 180 / M_PI);

  const auto model = blockMeans(cloud, args.cell_m);
  std::mt19937_64 rng(args.seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  mapping::GlobalOptions options;
  options.cell_m = args.cell_m;
  std::vector<double> err_m, err_deg, seconds;
  int found = 0;
  for (int w = 0; w < args.windows; ++w) {
    const double reach = 0.5 * args.window_m + args.cell_m;
    const Eigen::Vector2d centre(lo.x() + reach + u(rng) * (hi.x() - lo.x() - 2 * reach),
                                 lo.y() + reach + u(rng) * (hi.y() - lo.y() - 2 * reach));
    const double yaw = 2 * M_PI * u(rng);
    const Eigen::Rotation2Dd unturn(-yaw);
    mapping::Cloud scan;  // about the window's centre, turned by -yaw
    for (const auto& p : cloud)
      if ((p.head<2>() - centre).norm() < 0.5 * args.window_m) {
        const Eigen::Vector2d xy = unturn * (p.head<2>() - centre);
        scan.emplace_back(xy.x(), xy.y(), p.z());
      }
    start = std::chrono::steady_clock::now();
    const auto r = mapping::localize(scan, Eigen::Matrix3d::Identity(), model, options)
                       .value_or(mapping::Registration{});
    seconds.push_back(millisecondsSince(start) / 1000);
    err_m.push_back((r.transform.translation().head<2>() - centre).norm());
    const double got = std::atan2(r.transform.linear()(1, 0), r.transform.linear()(0, 0));
    err_deg.push_back(std::abs(std::remainder(got - yaw, 2 * M_PI)) * 180 / M_PI);
    found += err_m.back() < 0.5 * args.cell_m && err_deg.back() < 2.0;
  }
  return {{"dem", args.dem},
          {"points", cloud.size()},
          {"extent_m", {hi.x() - lo.x(), hi.y() - lo.y()}},
          {"spacing_m", spacing},
          {"mesh_triangles", mesh.size()},
          {"mesh_ms", mesh_ms},
          {"path",
           {{"found", path.found},
            {"reason", path.reason},
            {"len_m", path.length_m},
            {"waypoints", path.simplified.size()},
            {"raw_waypoints", path.raw.size()},
            {"cost_value", path.simplified_cost},
            {"raw_cost_value", path.raw_cost},
            {"steepest_triangle_deg", steepest},
            {"max_slope_deg", args.max_slope_deg},
            {"ms", path_ms}}},
          {"global_loc",
           {{"windows", args.windows},
            {"window_m", args.window_m},
            {"model_cell_m", args.cell_m},
            {"success_rate", double(found) / args.windows},
            {"success_rule", "within half a model cell and 2 deg"},
            {"err_m", distribution(err_m)},
            {"err_deg", distribution(err_deg)},
            {"s", distribution(seconds)}}}};
}

struct RegisterArgs {
  std::string source, target, initial = "0,0,0,0,0,0", about = "0,0,0", out;
  bool global = false;
  bool ignore_viewpoint = false;
  double cell_m = 1.0;
  bool json = true;  // the only output form
};

// X,Y,Z [m],ROLL,PITCH,YAW [deg] (or X,Y,Z,YAW), the turn R = Rz Ry Rx
// about `about`: a source point p goes to R (p - about) + about + (X,Y,Z).
Eigen::Isometry3d guessFrom(const std::string& text, const std::string& about_text) {
  const bool full = std::count(text.begin(), text.end(), ',') != 3;
  const auto v = parseNumbers(text, full ? 6 : 4, "--initial",
                              "X,Y,Z,ROLL_DEG,PITCH_DEG,YAW_DEG (or X,Y,Z,YAW_DEG)");
  const auto a = parseNumbers(about_text, 3, "--about", "X,Y,Z");
  const double deg = M_PI / 180;
  const double roll = full ? v[3] : 0, pitch = full ? v[4] : 0, yaw = full ? v[5] : v[3];
  requireTurn(roll, "--initial roll");
  requireTurn(pitch, "--initial pitch");
  requireTurn(yaw, "--initial yaw");
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(yaw * deg, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(pitch * deg, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(roll * deg, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  const Eigen::Vector3d about(a[0], a[1], a[2]);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = r;
  pose.translation() = about - r * about + Eigen::Vector3d(v[0], v[1], v[2]);
  return pose;
}

nlohmann::json qualityJson(const mapping::RegistrationQuality& q) {
  auto finite = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  return {{"verdict", mapping::verdictName(q.verdict)},
          {"reason", q.reason},
          {"overlap", q.overlap},
          {"partners", q.partners},
          {"height_agreement", finite(q.agreement)},
          {"rms_m", q.rms_m},
          {"self_rms_m", q.self_rms_m},
          {"weakest_axis", q.weakest_axis},
          {"weakest_sigma_m", finite(q.weakest_sigma_m)},
          {"sigma_m", {finite(q.sigma[0]), finite(q.sigma[1]), finite(q.sigma[2])}},
          {"sigma_deg",
           {finite(q.sigma[3] * 180 / M_PI), finite(q.sigma[4] * 180 / M_PI),
            finite(q.sigma[5] * 180 / M_PI)}}};
}

// Both files read side by side; the source's error first when both fail,
// as when read one after the other.
std::pair<mapping::ScanFile, mapping::ScanFile> readBoth(const std::string& source,
                                                         const std::string& target) {
  return sideBySide([&] { return mapping::readScan(source); },
                    [&] { return mapping::readScan(target); });
}

void runRegister(const RegisterArgs& args) {
  const auto start = std::chrono::steady_clock::now();
  const auto guess = guessFrom(args.initial, args.about);
  auto [source_file, target_file] = readBoth(args.source, args.target);
  auto& [source, source_scanner] = source_file;
  auto& [target, target_scanner] = target_file;
  const double read_ms = millisecondsSince(start);
  mapping::Registration r;
  if (args.global) {
    mapping::GlobalOptions options;
    options.cell_m = args.cell_m;
    const auto found = mapping::localize(source, Eigen::Matrix3d::Identity(), target, options);
    if (!found) throw std::runtime_error("no placement of the source overlaps the model enough");
    r = *found;
  } else {
    mapping::ScannerOrigins scanners;
    if (!args.ignore_viewpoint) scanners = {source_scanner, target_scanner};
    r = mapping::registerClouds(source, target, guess, {}, scanners);
  }
  const double ms = millisecondsSince(start);
  if (!args.out.empty())
    mapping::writeCloud(args.out, mapping::transformed(source, r.transform),
                        r.transform * source_scanner.value_or(Eigen::Vector3d::Zero()));
  const Eigen::Matrix4d m = r.transform.matrix();
  const Eigen::Vector3d t = r.transform.translation();
  printJson({{"source", args.source},
             {"target", args.target},
             {"mode", args.global ? "global" : "icp"},
             {"transform", matrixJson(r.transform)},
             {"translation_m", {t.x(), t.y(), t.z()}},
             {"yaw_deg", std::atan2(m(1, 0), m(0, 0)) * 180 / M_PI},
             {"converged", r.converged},
             {"iterations", r.iterations},
             {"pairs", r.pairs},
             {"rms_m", r.rms_m},
             {"quality", qualityJson(r.quality)},
             {"read_ms", read_ms},
             {"ms", ms}});
  if (r.quality.verdict == mapping::Verdict::kNoOverlap)
    throw std::runtime_error("the clouds do not overlap: " + r.quality.reason);
}

struct MeshArgs {
  std::string cloud, out;
  mapping::MeshOptions options;
  bool json = true;  // the only output form
};

void runMesh(const MeshArgs& args) {
  const auto cloud = mapping::readCloud(args.cloud);
  const auto start = std::chrono::steady_clock::now();
  const auto mesh = mapping::triangulate(cloud, args.options);
  const double ms = millisecondsSince(start);
  mapping::writeMesh(args.out, mesh);
  double smallest = INFINITY, largest = 0;
  for (int t = 0; t < int(mesh.size()); ++t)
    smallest = std::min(smallest, mesh.areaXY(t)), largest = std::max(largest, mesh.areaXY(t));
  printJson({{"cloud", args.cloud},
             {"points", cloud.size()},
             {"mesh", args.out},
             {"vertices", mesh.vertices.size()},
             {"mesh_triangles", mesh.size()},
             {"triangle_area_m2", {{"min", smallest}, {"max", largest}}},
             {"ms", ms}});
}

struct PathArgs {
  std::string mesh, from, to, cost = "slope";
  mapping::PathOptions options;
  bool json = true;  // the only output form
};

nlohmann::json toJson(const std::vector<Eigen::Vector3d>& points) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& p : points) out.push_back({p.x(), p.y(), p.z()});
  return out;
}

void runPath(const PathArgs& args) {
  const auto mesh = mapping::readMesh(args.mesh);
  auto options = args.options;
  options.cost = args.cost == "distance"     ? mapping::PathCost::kDistance
                 : args.cost == "highground" ? mapping::PathCost::kHighGround
                                             : mapping::PathCost::kSlope;
  const auto from = parseNumbers(args.from, 2, "--from", "X,Y");
  const auto to = parseNumbers(args.to, 2, "--to", "X,Y");
  const auto start = std::chrono::steady_clock::now();
  const auto path = mapping::planPath(mesh, {from[0], from[1]}, {to[0], to[1]}, options);
  const double ms = millisecondsSince(start);
  if (!path.found) throw std::runtime_error("no path: " + path.reason);
  printJson({{"mesh", args.mesh},
             {"cost", args.cost},
             {"max_slope_deg", options.max_slope_deg},
             {"triangles", path.triangles.size()},
             {"waypoints", toJson(path.simplified)},
             {"raw_waypoints", path.raw.size()},
             {"path_len_m", path.length_m},
             {"cost_value", path.simplified_cost},
             {"raw_cost_value", path.raw_cost},
             {"path_ms", ms}});
}

}  // namespace

void addRegister(CLI::App& app) {
  auto args = std::make_shared<RegisterArgs>();
  auto* cmd = app.add_subcommand(
      "register",
      "Align SOURCE to TARGET: ICP from an initial pose (dead reckoning), or --global: "
      "localize a levelled scan in a coarse model without a prior");
  cmd->add_option("source", args->source, "point cloud to move (.pcd, x y z in metres)")
      ->required();
  cmd->add_option("target", args->target, "point cloud or coarse model (.pcd)")->required();
  cmd->add_option("--initial", args->initial,
                  "source-to-target guess to start from: X,Y,Z [m],ROLL,PITCH,YAW [deg] "
                  "(R = Rz Ry Rx, turning about --about), or X,Y,Z,YAW")
      ->capture_default_str();
  cmd->add_option("--about", args->about,
                  "the point of the source's frame the guess turns about, X,Y,Z [m] (the "
                  "scanner, say)")
      ->capture_default_str();
  cmd->add_flag("--global", args->global,
                "no prior: TARGET is a model on a regular grid, SOURCE a scan with z up");
  cmd->add_flag("--ignore-viewpoint", args->ignore_viewpoint,
                "the PCD files' VIEWPOINT is not where their scanner stood: use the points as "
                "they are (default: each point is moved along its ray from there onto the "
                "surface around it, docs/mapping.md)");
  cmd->add_option("--cell", args->cell_m, "--global: the model's grid spacing [m]")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  cmd->add_option("--out", args->out, "write the moved source here (.pcd)");
  cmd->add_flag("--json", args->json, "print JSON (the only output form)");
  cmd->callback([args] { runRegister(*args); });
}

void addMesh(CLI::App& app) {
  auto args = std::make_shared<MeshArgs>();
  auto* cmd = app.add_subcommand(
      "mesh", "Irregular triangulated terrain of a point cloud (few triangles where flat)");
  cmd->add_option("--cloud", args->cloud, "point cloud (.pcd, x y z in metres)")->required();
  cmd->add_option("--out", args->out, "mesh to write (.ply)")->required();
  cmd->add_option("--tolerance", args->options.tolerance_m,
                  "largest height error of a flat square's two triangles [m]")
      ->check(CLI::Range(1e-4, 1000.0))
      ->capture_default_str();
  cmd->add_option("--min-cell", args->options.min_cell_m, "smallest square [m]")
      ->check(CLI::Range(1e-3, 1e5))
      ->capture_default_str();
  cmd->add_option("--max-cell", args->options.max_cell_m, "largest square [m]")
      ->check(CLI::Range(1e-3, 1e5))
      ->capture_default_str();
  cmd->add_flag("--json", args->json, "print JSON (the only output form)");
  cmd->callback([args] { runMesh(*args); });
}

void addPath(CLI::App& app) {
  auto args = std::make_shared<PathArgs>();
  auto* cmd = app.add_subcommand(
      "path", "Path over a triangulated terrain: Dijkstra on the triangle graph, simplified");
  cmd->add_option("--mesh", args->mesh, "mesh (.ply, from ambler-cli mesh)")->required();
  cmd->add_option("--from", args->from, "start X,Y [m]")->required();
  cmd->add_option("--to", args->to, "goal X,Y [m]")->required();
  cmd->add_option("--cost", args->cost, "edge cost")
      ->check(CLI::IsMember({"distance", "slope", "highground"}))
      ->capture_default_str();
  cmd->add_option("--max-slope-deg", args->options.max_slope_deg,
                  "triangles steeper than this are not entered [deg]")
      ->check(CLI::Range(0.1, 89.9))
      ->capture_default_str();
  cmd->add_flag("--json", args->json, "print JSON (the only output form)");
  cmd->callback([args] { runPath(*args); });
}

void addEvalDem(CLI::App& eval, Evaluations& all) {
  all.push_back({"dem", [] { return evalDem(EvalDemArgs{}); }});
  auto args = std::make_shared<EvalDemArgs>();
  auto* cmd = eval.add_subcommand(
      "dem",
      "Real terrain: a USGS elevation model meshed, a path across it under a slope limit, and "
      "windows of it found without a prior in its block-mean model");
  cmd->add_option("--dem", args->dem, "DEM (.npz in matplotlib's sample layout)")
      ->capture_default_str();
  cmd->add_option("--windows", args->windows, "windows to localize")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_option("--window", args->window_m, "window diameter [m]")
      ->check(CLI::Range(1.0, 1e6))
      ->capture_default_str();
  cmd->add_option("--cell", args->cell_m, "model cell [m]")
      ->check(CLI::Range(0.01, 1e5))
      ->capture_default_str();
  cmd->add_option("--max-slope-deg", args->max_slope_deg, "the path's slope limit [deg]")
      ->check(CLI::Range(0.1, 89.9))
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "windows' places and headings")->capture_default_str();
  cmd->add_flag("--json", args->json, "print JSON (the only output form)");
  cmd->callback([args] { printJson(evalDem(*args)); });
}

void addEvalMapping(CLI::App& eval, Evaluations& all) {
  all.push_back({"mapping", [] { return evalMapping(EvalMappingArgs{}); }});
  auto args = std::make_shared<EvalMappingArgs>();
  auto* cmd = eval.add_subcommand(
      "mapping",
      "Registration of simulated scans from two viewpoints (ICP from dead reckoning) and "
      "global localization of a scan in a 1 m model, against the simulator's poses");
  cmd->add_option("--seeds", args->seeds, "course seeds, one case each")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_flag("--json", args->json, "print JSON (the only output form)");
  cmd->callback([args] { printJson(evalMapping(*args)); });
}

}  // namespace ambler::cli
