#include <filesystem>
#include <memory>

#include "cli/Arguments.h"
#include "cli/Commands.h"
#include "core/Angles.h"
#include "core/Resources.h"
#include "io/Json.h"
#include "io/Tiff.h"
#include "mapping/Localization.h"
#include "mapping/MappingFiles.h"
#include "sensor/RangeImageFile.h"
#include "sensor/StriperImageFile.h"
#include "sim/CourseScene.h"
#include "sim/StriperSim.h"
#include "sim/TerrainFamilies.h"

namespace ambler::cli {

namespace {

// The course's model from orbital altimetry that sim-scan writes.
constexpr Box2 kModelRegion{-30.0, -30.0, 30.0, 30.0};

struct SimScanArgs {
  std::uint64_t seed = 1;
  std::string family = "course";
  std::string out;
  std::string config;
  std::optional<double> tilt_deg, height_m, noise_k;
  std::optional<int> rows, cols;
  std::string region;
  double resolution = 0.05;
  std::string at = "0,0,0";
};

sim::ScannerModel scannerModel(const SimScanArgs& a) {
  auto m = sim::readScannerModel(a.config.empty() ? findResource("config/scanner.json")
                                                  : std::filesystem::path(a.config));
  if (a.rows || a.cols) {
    const double vfov = std::abs(m.geometry.phi_step) * m.geometry.rows;
    const double hfov = std::abs(m.geometry.theta_step) * m.geometry.cols;
    m.geometry = sensor::ScanGeometry::symmetric(a.rows.value_or(m.geometry.rows),
                                                 a.cols.value_or(m.geometry.cols), vfov, hfov);
  }
  if (a.tilt_deg) m.tilt = *a.tilt_deg * kDeg;
  if (a.height_m) m.mount_height = *a.height_m;
  if (a.noise_k) m.range_sigma_k = *a.noise_k;
  return m;
}

void writeTruth(const sim::VisibilityTruth& truth, const std::filesystem::path& dir) {
  io::writeTiff(dir / "truth_z.tif", truth.height);
  io::writeTiff(dir / "truth_visible.tif", truth.state);
  auto header = io::gridJson(truth.grid);
  header["frame"] = "world";
  header["truth_visible_codes"] = {
      {"0", "visible"}, {"1", "outside field of view"}, {"2", "occluded"}};
  io::writeJsonFile(dir / "truth.json", header);
}

void runSimScan(const SimScanArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  const auto at = parseRoverAt(a.at);
  const auto family = sim::parseFamily(a.family);
  if (!family) throw CLI::ValidationError("--family", "unknown terrain family '" + a.family + "'");
  const sim::CourseScene scene(sim::makeFamilyTerrain(*family, a.seed), scannerModel(a), at.xy,
                               at.heading_deg * kDeg);
  const auto scan_start = std::chrono::steady_clock::now();
  const auto scan = scene.scan(a.seed);
  const double scan_ms = millisecondsSince(scan_start);

  const Box2 region = a.region.empty() ? scene.footprint() : parseRegion(a.region);
  const auto grid = gridOver(region, a.resolution, "truth grid");
  const auto truth_start = std::chrono::steady_clock::now();
  const auto truth = scene.truth(grid);
  const double truth_ms = millisecondsSince(truth_start);

  const std::filesystem::path dir(a.out);
  std::filesystem::create_directories(dir);
  sensor::writeRangeImage(scan, dir / "scan.tif");
  // The same returns as a point cloud in the world frame (for mesh, path),
  // and levelled about the sensor, as the rover's inclinometers leave it
  // without knowing where or which way it is (for register --global), with
  // the course's model from orbital altimetry.
  mapping::writeCloud(dir / "cloud.pcd", scan.pointsInWorld(), scan.sensor_to_world.translation());
  mapping::Cloud level;
  const Eigen::Matrix3d tilt = mapping::withoutYaw(scan.sensor_to_world.linear());
  for (const auto& p : scan.pointsInSensor()) level.push_back(tilt * p);
  mapping::writeCloud(dir / "cloud_level.pcd", level);
  mapping::writeCloud(dir / "model.pcd",
                      sim::orbitalModel(scene.terrain(), GridSpec::covering(kModelRegion, 1.0)));
  writeTruth(truth, dir);
  printJson(
      {{"scan", (dir / "scan.tif").string()},
       {"cloud", (dir / "cloud.pcd").string()},
       {"sensor_pose",
        {{"x", scan.sensor_to_world.translation().x()},
         {"y", scan.sensor_to_world.translation().y()},
         {"z", scan.sensor_to_world.translation().z()},
         {"heading_deg", at.heading_deg}}},
       {"rows", scan.rows()},
       {"cols", scan.cols()},
       {"returns", scan.returnCount()},
       {"truth_grid", {{"rows", grid.rows}, {"cols", grid.cols}, {"resolution", grid.resolution}}},
       {"scan_ms", scan_ms},
       {"truth_ms", truth_ms},
       {"elapsed_ms", millisecondsSince(start)}});
}

}  // namespace

void addSimScan(CLI::App& app) {
  auto args = std::make_shared<SimScanArgs>();
  auto* cmd = app.add_subcommand(
      "sim-scan", "Simulate one laser range image of a terrain family, with ground truth");
  cmd->add_option("--seed", args->seed, "terrain and noise seed")->capture_default_str();
  cmd->add_option("--family", args->family, "terrain family: " + sim::familyNamesListed())
      ->capture_default_str();
  cmd->add_option("--out", args->out, "output folder")->required();
  cmd->add_option("--config", args->config, "scanner model JSON (default: config/scanner.json)");
  cmd->add_option("--tilt", args->tilt_deg, "boresight depression [deg]")
      ->check(CLI::Range(-89.0, 89.0));
  cmd->add_option("--height", args->height_m, "sensor height above ground [m]")
      ->check(CLI::Range(0.1, 100.0));
  cmd->add_option("--rows", args->rows, "image rows")->check(CLI::Range(1, 8192));
  cmd->add_option("--cols", args->cols, "image columns")->check(CLI::Range(1, 8192));
  cmd->add_option("--noise", args->noise_k, "range noise k in sigma = k rho^2 [1/m]")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--region", args->region,
                  "ground-truth region XMIN,YMIN,XMAX,YMAX [m] (default: scan footprint)");
  cmd->add_option("--resolution", args->resolution, "ground-truth cell size [m]")
      ->check(CLI::Range(0.001, 10.0))
      ->capture_default_str();
  cmd->add_option("--at", args->at, "rover position X,Y [m] and heading [deg, 0: +y]")
      ->capture_default_str();
  cmd->callback([args] { runSimScan(*args); });
}

void addSimStriper(CLI::App& app) {
  struct Args {
    std::uint64_t seed = 1;
    std::string out;
    int rocks = 5;
    double noise = 0.0005;
    std::string burial = "0.5,0.75";
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("sim-striper",
                                 "Simulate a light-striper image of the rock-sampling work area");
  cmd->add_option("--seed", args->seed, "scene and noise seed")->capture_default_str();
  cmd->add_option("--out", args->out, "output folder")->required();
  cmd->add_option("--rocks", args->rocks, "number of rocks")
      ->check(CLI::Range(0, 40))
      ->capture_default_str();
  cmd->add_option("--noise", args->noise, "noise along the camera ray [m]")
      ->check(CLI::Range(0.0, 0.05))
      ->capture_default_str();
  cmd->add_option("--burial", args->burial,
                  "MIN,MAX share of each rock's height in the sand, from 0 (resting on it) to 1")
      ->capture_default_str();
  cmd->callback([args] {
    const auto start = std::chrono::steady_clock::now();
    const auto burial = parseNumbers(args->burial, 2, "--burial", "MIN,MAX");
    if (!(burial[0] >= 0 && burial[0] <= burial[1] && burial[1] <= 1))
      throw std::invalid_argument("--burial must be MIN,MAX with 0 <= MIN <= MAX <= 1");
    const sim::ProceduralTerrain terrain(sim::makeWorkArea({.seed = args->seed,
                                                            .rocks = args->rocks,
                                                            .burial_min = burial[0],
                                                            .burial_max = burial[1]}));
    sim::StriperModel model;
    model.noise_sigma = args->noise;
    const auto scene = sim::simulateStriper(terrain, model, args->seed);
    const std::filesystem::path dir(args->out);
    sensor::writeStriperImage(scene.image, dir);
    io::writeTiff(dir / "truth_labels.tif", scene.labels);
    printJson({{"striper", dir.string()},
               {"points", scene.image.pointCount()},
               {"rocks", terrain.description().features.size()},
               {"elapsed_ms", millisecondsSince(start)}});
  });
}

}  // namespace ambler::cli
