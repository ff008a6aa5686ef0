#include <iostream>
#include <map>
#include <memory>

#include "cli/Arguments.h"
#include "cli/Commands.h"
#include "core/Resources.h"
#include "sim/CourseScene.h"
#include "terrain/Binning.h"
#include "terrain/Locus.h"
#include "terrain/MapScore.h"

namespace ambler::cli {

namespace {

constexpr double kDeg = M_PI / 180.0;

struct EvalElevationArgs {
  std::vector<std::uint64_t> seeds{1, 2, 3};
  std::vector<double> noise_k{0.0, 1e-4, 2e-4, 4e-4};
  std::vector<double> tilts_deg{20.0, 30.0, 40.0};
  std::string region = "-10,3,10,23";
  double resolution = 0.05;
  int threads = 1;
  terrain::OccludingEdgeOptions edges;
  bool json = false;
};

// Scores of one method, pooled over all scenes and per noise level.
struct MethodResult {
  terrain::MapScore all;
  std::map<double, terrain::MapScore> by_noise;
  double total_ms = 0.0;
  int maps = 0;
};

nlohmann::json optionalNumber(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

nlohmann::json scoreJson(const terrain::MapScore& s) {
  return {{"rmse_m", optionalNumber(s.rmse())},
          {"coverage", optionalNumber(s.coverage())},
          {"shadow_recall", optionalNumber(s.shadowRecall())},
          {"shadow_precision", optionalNumber(s.shadowPrecision())},
          {"sigma_calibration", optionalNumber(s.sigmaCalibration())},
          {"known_cells", s.knownCells()}};
}

nlohmann::json methodJson(const MethodResult& m) {
  auto j = scoreJson(m.all);
  j["ms_per_map"] = m.maps ? m.total_ms / m.maps : 0.0;
  j["by_noise"] = nlohmann::json::array();
  for (const auto& [k, score] : m.by_noise) {
    auto level = scoreJson(score);
    level["noise_k"] = k;
    j["by_noise"].push_back(level);
  }
  return j;
}

template <typename Build>
void scoreMethod(MethodResult& result, double k, const sim::VisibilityTruth& truth, Build&& build) {
  const auto start = std::chrono::steady_clock::now();
  const auto map = build();
  result.total_ms += millisecondsSince(start);
  ++result.maps;
  // Without noise sigma is only an interpolation bound: not a calibration.
  result.all.add(map, truth.height, truth.state, k > 0);
  result.by_noise[k].add(map, truth.height, truth.state, k > 0);
}

void printTable(const nlohmann::json& report) {
  std::cout << "method   noise_k   rmse_m   coverage  shadow_recall  shadow_precision  "
               "sigma_calibration\n";
  for (const auto& [name, m] : report["methods"].items())
    for (const auto& level : m["by_noise"]) {
      std::cout << name << "  " << level["noise_k"] << "  ";
      for (const char* key :
           {"rmse_m", "coverage", "shadow_recall", "shadow_precision", "sigma_calibration"})
        std::cout << level[key] << "  ";
      std::cout << "\n";
    }
}

nlohmann::json evalElevation(const EvalElevationArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  const auto base = sim::readScannerModel(findResource("config/scanner.json"));
  const Box2 region = parseRegion(a.region);
  MethodResult locus, binning;
  terrain::LocusOptions options;
  options.threads = a.threads;
  options.edges = a.edges;
  int scenes = 0;
  for (const double tilt : a.tilts_deg)
    for (const auto seed : a.seeds) {
      auto model = base;
      model.tilt = tilt * kDeg;
      const sim::CourseScene scene(seed, model);
      const auto grid = GridSpec::covering(region, a.resolution);
      const auto truth = scene.truth(grid);
      for (const double k : a.noise_k) {
        auto noisy = model;
        noisy.range_sigma_k = k;
        const auto image = sim::simulateScan(scene.caster(), noisy, scene.sensorPose(), seed);
        scoreMethod(locus, k, truth, [&] { return terrain::buildLocusMap(image, grid, options); });
        scoreMethod(binning, k, truth, [&] { return terrain::buildBinnedMap(image, grid); });
        ++scenes;
      }
    }
  const nlohmann::json report{
      {"scenes", scenes},
      {"seeds", a.seeds},
      {"noise_k", a.noise_k},
      {"tilts_deg", a.tilts_deg},
      {"region", a.region},
      {"resolution", a.resolution},
      {"threads", a.threads},
      {"min_grazing_deg", a.edges.min_grazing_deg},
      {"edge_noise_sigmas", a.edges.noise_sigmas},
      {"methods", {{"locus", methodJson(locus)}, {"binning", methodJson(binning)}}},
      {"elapsed_ms", millisecondsSince(start)}};
  return report;
}

}  // namespace

void addEval(CLI::App& app) {
  auto* eval = app.add_subcommand("eval", "Measure the algorithms against simulator ground truth");
  eval->require_subcommand(1);
  auto args = std::make_shared<EvalElevationArgs>();
  auto* cmd = eval->add_subcommand(
      "elevation", "Locus method vs Cartesian binning on simulated scans of the obstacle course");
  cmd->add_option("--seeds", args->seeds, "course seeds")->delimiter(',')->capture_default_str();
  cmd->add_option("--noise", args->noise_k, "range noise levels k [1/m]")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 0.01))
      ->capture_default_str();
  cmd->add_option("--tilts", args->tilts_deg, "scanner tilts [deg]")
      ->delimiter(',')
      ->check(CLI::Range(5.0, 80.0))
      ->capture_default_str();
  cmd->add_option("--region", args->region,
                  "map area XMIN,YMIN,XMAX,YMAX [m]; the rover stands at the origin facing +y")
      ->capture_default_str();
  cmd->add_option("--resolution", args->resolution, "map cell size [m]")
      ->check(CLI::Range(0.01, 1.0))
      ->capture_default_str();
  cmd->add_option("--threads", args->threads, "threads for the locus method (timing)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  addEdgeOptions(*cmd, args->edges);
  cmd->add_flag("--json", args->json, "print one JSON object instead of a table");
  cmd->callback([args] {
    const auto report = evalElevation(*args);
    if (args->json)
      printJson(report);
    else
      printTable(report);
  });
  auto all = std::make_shared<Evaluations>();
  all->push_back({"elevation", [] {
                    EvalElevationArgs defaults;
                    return evalElevation(defaults);
                  }});
  addEvalWalk(*eval, *all);
  addEvalLink(*eval, *all);
  addEvalRocks(*eval, *all);
  addEvalMapping(*eval, *all);
  addEvalDem(*eval, *all);
  addEvalDanger(*eval, *all);
  addEvalAll(*eval, all);
}

}  // namespace ambler::cli
