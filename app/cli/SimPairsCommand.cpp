// `sim-pairs`: pairs of simulated scans on the terrain families for
// measuring registration (bench/registration), each written twice: levelled
// about its sensor and in the world frame, with the truth and the initial
// guess for both.
#include <cstdio>
#include <filesystem>

#include "cli/Arguments.h"
#include "cli/Commands.h"
#include "core/Resources.h"
#include "io/Json.h"
#include "mapping/MappingFiles.h"
#include "sim/ScanPairs.h"

namespace ambler::cli {

namespace {

// "X,Y,Z,ROLL,PITCH,YAW" (m, deg) of a guess that turns about `about`.
std::string guessText(const Eigen::Isometry3d& guess, const Eigen::Vector3d& about) {
  const Eigen::Matrix3d r = guess.linear();
  const Eigen::Vector3d t = guess * about - about;
  const double deg = 180 / M_PI;
  char text[200];
  std::snprintf(text, sizeof text, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g", t.x(), t.y(), t.z(),
                std::atan2(r(2, 1), r(2, 2)) * deg,
                std::asin(-std::clamp(r(2, 0), -1.0, 1.0)) * deg,
                std::atan2(r(1, 0), r(0, 0)) * deg);
  return text;
}

std::string pointText(const Eigen::Vector3d& p) {
  char text[100];
  std::snprintf(text, sizeof text, "%.9g,%.9g,%.9g", p.x(), p.y(), p.z());
  return text;
}

struct SimPairsArgs {
  std::string out;
  bool tuning = false;
  int count = 24;
  int foreign = 4;
  std::vector<double> noise_k = sim::ScanPairOptions{}.noise_k;
  std::vector<double> distance_m{1.0, 5.0}, turn_deg{5.0, 30.0};
};

void runSimPairs(const SimPairsArgs& a) {
  const auto scanner = sim::readScannerModel(findResource("config/scanner.json"));
  const std::filesystem::path dir(a.out);
  std::filesystem::create_directories(dir);
  const std::uint64_t first = a.tuning ? 1 : 1001;
  nlohmann::json pairs = nlohmann::json::array();
  for (int i = 0; i < a.count + a.foreign; ++i) {
    const auto family = sim::kTerrainFamilies[std::size_t(i) % sim::kTerrainFamilies.size()];
    sim::ScanPairOptions options;
    options.foreign = i >= a.count;
    options.noise_k = a.noise_k;
    options.min_distance_m = a.distance_m[0], options.max_distance_m = a.distance_m[1];
    options.min_turn_deg = a.turn_deg[0], options.max_turn_deg = a.turn_deg[1];
    const auto pair = sim::makeScanPair(family, first + std::uint64_t(i), scanner, options);
    char name[16];
    std::snprintf(name, sizeof name, "%03d", i);
    const auto sub = dir / name;
    std::filesystem::create_directories(sub);
    mapping::writeCloud(sub / "source_level.pcd", pair.source);
    mapping::writeCloud(sub / "target_level.pcd", pair.target);
    mapping::writeCloud(sub / "source_world.pcd",
                        mapping::transformed(pair.source, pair.source_to_world),
                        pair.source_to_world.translation());
    mapping::writeCloud(sub / "target_world.pcd",
                        mapping::transformed(pair.target, pair.target_to_world),
                        pair.target_to_world.translation());
    const Eigen::Vector3d sensor = pair.source_to_world.translation();
    pairs.push_back({{"name", name},
                     {"family", sim::familyName(family)},
                     {"seed", pair.seed},
                     {"foreign", pair.foreign},
                     {"distance_m", pair.distance_m},
                     {"turn_deg", pair.turn_deg},
                     {"noise_k", pair.noise_k},
                     {"guess_error_m", pair.error_m},
                     {"guess_error_deg", pair.error_deg},
                     {"levelled",
                      {{"source", (sub / "source_level.pcd").string()},
                       {"target", (sub / "target_level.pcd").string()},
                       {"truth", matrixJson(pair.levelledTruth())},
                       {"guess", matrixJson(pair.levelledGuess())},
                       {"initial", guessText(pair.levelledGuess(), Eigen::Vector3d::Zero())},
                       {"about", pointText(Eigen::Vector3d::Zero())}}},
                     {"world",
                      {{"source", (sub / "source_world.pcd").string()},
                       {"target", (sub / "target_world.pcd").string()},
                       {"truth", matrixJson(Eigen::Isometry3d::Identity())},
                       {"guess", matrixJson(pair.worldGuess())},
                       {"initial", guessText(pair.worldGuess(), sensor)},
                       {"about", pointText(sensor)}}}});
  }
  nlohmann::json doc = {{"set", a.tuning ? "tuning" : "evaluation"},
                        {"first_seed", first},
                        {"success_rule", "within 1 % of the distance and 0.5 deg"},
                        {"pairs", pairs}};
  io::writeJsonFile(dir / "pairs.json", doc);
  printJson({{"pairs", (dir / "pairs.json").string()},
             {"count", a.count},
             {"foreign", a.foreign},
             {"set", doc["set"]}});
}

}  // namespace

void addSimPairs(CLI::App& app) {
  auto args = std::make_shared<SimPairsArgs>();
  auto* cmd = app.add_subcommand(
      "sim-pairs",
      "Simulate pairs of scans on the terrain families, with truth and initial guesses, for "
      "measuring registration (bench/registration)");
  cmd->add_option("--out", args->out, "output folder (pairs.json and one folder per pair)")
      ->required();
  cmd->add_flag("--tuning", args->tuning,
                "the tuning pairs (seeds from 1) instead of the evaluation pairs (from 1001)");
  cmd->add_option("--count", args->count, "overlapping pairs, the families in turn")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  cmd->add_option("--foreign", args->foreign,
                  "pairs whose clouds are of two different terrains, to be refused")
      ->check(CLI::Range(0, 10000))
      ->capture_default_str();
  cmd->add_option("--noise", args->noise_k,
                  "range noise k in sigma = k rho^2 [1/m]; each pair draws one of these")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 0.01))
      ->capture_default_str();
  cmd->add_option("--distance", args->distance_m, "MIN,MAX between the two scanners [m]")
      ->delimiter(',')
      ->expected(2)
      ->check(CLI::Range(0.0, 30.0))
      ->capture_default_str();
  cmd->add_option("--turn", args->turn_deg, "MIN,MAX between their headings [deg]")
      ->delimiter(',')
      ->expected(2)
      ->check(CLI::Range(0.0, 90.0))
      ->capture_default_str();
  cmd->callback([args] { runSimPairs(*args); });
}

}  // namespace ambler::cli
