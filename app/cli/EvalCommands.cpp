#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include "cli/Arguments.h"
#include "cli/Commands.h"
#include "core/Angles.h"
#include "core/Resources.h"
#include "footfall/Criteria.h"
#include "footfall/FootfallConfig.h"
#include "sim/CourseScene.h"
#include "sim/TerrainFamilies.h"
#include "terrain/Binning.h"
#include "terrain/Locus.h"
#include "terrain/MapScore.h"

namespace ambler::cli {

namespace {

// A scanner placement of the evaluation: height above the ground under the
// rover and tilt of the boresight.
struct SensorPose {
  double height_m = 5.0;
  double tilt_deg = 30.0;
};

struct EvalElevationArgs {
  std::vector<std::string> families;  // empty: all
  std::vector<std::uint64_t> seeds;   // empty: the evaluation seeds
  bool tuning = false;                // the tuning seeds instead
  std::vector<double> noise_k{0.0, 2.5e-4, 5e-4, 1e-3};
  std::vector<std::string> poses{"1.5:12", "3:25", "5:30", "6:45"};
  std::string region = "-10,3,10,23";
  double resolution = 0.05;
  terrain::LocusOptions locus = [] {
    terrain::LocusOptions o;
    o.threads = 1;  // timing on one core
    return o;
  }();
  bool json = false;
};

// Where the best foothold of a map lands: on cells that were seen, or
// not (truly occluded or outside the view) under the foot.
struct FootholdCount {
  int chosen = 0;
  int on_unseen = 0;
};

// Scores of one method, pooled over all scenes and per noise level.
struct MethodResult {
  terrain::MapScore all;
  std::map<double, terrain::MapScore> by_noise;
  FootholdCount footholds;
  std::map<double, FootholdCount> footholds_by_noise;
  double total_ms = 0.0;
  int maps = 0;
};

nlohmann::json optionalNumber(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

nlohmann::json scoreJson(const terrain::MapScore& s) {
  return {{"rmse_m", optionalNumber(s.rmse())},
          {"coverage", optionalNumber(s.coverage())},
          {"oblique_coverage", optionalNumber(s.obliqueCoverage())},
          {"shadow_recall", optionalNumber(s.shadowRecall())},
          {"shadow_precision", optionalNumber(s.shadowPrecision())},
          {"shadow_recall_within_1_cell", optionalNumber(s.shadowRecallWithin1())},
          {"shadow_precision_within_1_cell", optionalNumber(s.shadowPrecisionWithin1())},
          {"shadow_out_of_view", optionalNumber(s.shadowOutOfView())},
          {"occluded_known", optionalNumber(s.occludedKnown())},
          {"occluded_known_far", s.occludedKnownFar()},
          {"occluded_known_error_p50_m", optionalNumber(s.occludedKnownError(0.5))},
          {"occluded_known_error_p95_m", optionalNumber(s.occludedKnownError(0.95))},
          {"sigma_calibration", optionalNumber(s.sigmaCalibration())},
          {"sigma_calibration_visible", optionalNumber(s.sigmaCalibrationVisible())},
          {"known_cells", s.knownCells()}};
}

nlohmann::json footholdJson(const FootholdCount& f) {
  return {{"footholds", f.chosen}, {"footholds_on_unseen_cells", f.on_unseen}};
}

// Nine foothold regions (squares of 1.5 m, smaller on a small map) spread
// over the map: at a quarter, half and three quarters of its width, a fifth,
// 45 % and 70 % of its depth, as the gait planner asks for one per leg move.
std::vector<Box2> footholdRegions(const Box2& map) {
  std::vector<Box2> regions;
  const double half = 0.5 * std::min(1.5, 0.2 * std::min(map.width(), map.height()));
  for (const double fx : {0.25, 0.5, 0.75})
    for (const double fy : {0.2, 0.45, 0.7}) {
      const double x = map.x_min + fx * map.width(), y = map.y_min + fy * map.height();
      regions.push_back({x - half, y - half, x + half, y + half});
    }
  return regions;
}

// The best foothold (krotkov1989's equilibrium criterion, the configured
// foot) in each region, and whether the truth has a cell under the foot
// that nobody saw.
FootholdCount scoreFootholds(const terrain::ElevationMap& map, const sim::VisibilityTruth& truth,
                             const std::vector<Box2>& regions, const footfall::FootOptions& foot) {
  FootholdCount count;
  const auto& g = truth.grid;
  const double radius = 0.5 * foot.diameter_m;
  for (const auto& region : regions) {
    const auto best = footfall::bestFoothold(
        footfall::evaluateFootfalls(map, region, footfall::Criterion::kEquilibrium, foot));
    if (!best.found) continue;
    ++count.chosen;
    // Only the cells around the foot can be under it.
    const int r0 = std::max(0, int(std::floor((best.y - radius - g.origin_y) / g.resolution)));
    const int r1 =
        std::min(g.rows - 1, int(std::floor((best.y + radius - g.origin_y) / g.resolution)));
    const int c0 = std::max(0, int(std::floor((best.x - radius - g.origin_x) / g.resolution)));
    const int c1 =
        std::min(g.cols - 1, int(std::floor((best.x + radius - g.origin_x) / g.resolution)));
    bool unseen = false;
    for (int r = r0; r <= r1 && !unseen; ++r)
      for (int c = c0; c <= c1 && !unseen; ++c) {
        const auto p = g.cellCenter(r, c);
        unseen = std::hypot(p.x() - best.x, p.y() - best.y) <= radius && truth.state(r, c) != 0;
      }
    count.on_unseen += unseen;
  }
  return count;
}

// One method's map of one scene, built once and timed, and where the best
// footholds on it landed.
struct BuiltMap {
  terrain::ElevationMap map;
  double ms = 0.0;
  FootholdCount footholds;
};

template <typename Build>
BuiltMap buildMap(Build&& build, const sim::VisibilityTruth& truth,
                  const std::vector<Box2>& regions, const footfall::FootOptions& foot) {
  const auto start = std::chrono::steady_clock::now();
  BuiltMap built{build(), 0.0, {}};
  built.ms = millisecondsSince(start);
  built.footholds = scoreFootholds(built.map, truth, regions, foot);
  return built;
}

void addMap(MethodResult& result, double k, const sim::VisibilityTruth& truth,
            const BuiltMap& built) {
  result.total_ms += built.ms;
  ++result.maps;
  // Without noise sigma is only an interpolation bound: not a calibration.
  result.all.add(built.map, truth.height, truth.state, k > 0);
  result.by_noise[k].add(built.map, truth.height, truth.state, k > 0);
  for (auto* total : {&result.footholds, &result.footholds_by_noise[k]}) {
    total->chosen += built.footholds.chosen;
    total->on_unseen += built.footholds.on_unseen;
  }
}

// The scores of both methods, pooled over what they were added from, and
// the two compared on the cells both know.
struct Scores {
  MethodResult locus, binning;
  terrain::SharedCellsScore shared;
  std::map<double, terrain::SharedCellsScore> shared_by_noise;

  void add(double k, const sim::VisibilityTruth& truth, const BuiltMap& by_locus,
           const BuiltMap& by_binning) {
    addMap(locus, k, truth, by_locus);
    addMap(binning, k, truth, by_binning);
    for (auto* s : {&shared, &shared_by_noise[k]})
      s->add(by_locus.map, by_binning.map, truth.height);
  }
};

// `shared_rmse` gives this method's RMSE on the cells both methods know.
nlohmann::json methodJson(const MethodResult& m, const Scores& s,
                          std::optional<double> (terrain::SharedCellsScore::*shared_rmse)() const) {
  auto sharedJson = [&](const terrain::SharedCellsScore& shared) {
    return nlohmann::json{{"rmse_on_shared_cells_m", optionalNumber((shared.*shared_rmse)())},
                          {"shared_cells", shared.cells()}};
  };
  auto j = scoreJson(m.all);
  j.update(footholdJson(m.footholds));
  j.update(sharedJson(s.shared));
  j["ms_per_map"] = m.maps ? m.total_ms / m.maps : 0.0;
  j["by_noise"] = nlohmann::json::array();
  for (const auto& [k, score] : m.by_noise) {
    auto level = scoreJson(score);
    if (const auto f = m.footholds_by_noise.find(k); f != m.footholds_by_noise.end())
      level.update(footholdJson(f->second));
    if (const auto shared = s.shared_by_noise.find(k); shared != s.shared_by_noise.end())
      level.update(sharedJson(shared->second));
    level["noise_k"] = k;
    j["by_noise"].push_back(level);
  }
  return j;
}

nlohmann::json methodsJson(const Scores& s) {
  return {{"locus", methodJson(s.locus, s, &terrain::SharedCellsScore::rmseFirst)},
          {"binning", methodJson(s.binning, s, &terrain::SharedCellsScore::rmseSecond)}};
}

// rmse_m and coverage first: scripts read them as the third and fourth
// columns (tests/packaging/PackageInstallTest.sh).
constexpr const char* kTableKeys[] = {"rmse_m",
                                      "coverage",
                                      "shadow_recall_within_1_cell",
                                      "shadow_precision_within_1_cell",
                                      "occluded_known",
                                      "occluded_known_far",
                                      "sigma_calibration",
                                      "footholds_on_unseen_cells",
                                      "sigma_calibration_visible",
                                      "occluded_known_error_p95_m"};

void printMethods(const std::string& prefix, const nlohmann::json& methods) {
  for (const auto& [name, m] : methods.items())
    for (const auto& level : m["by_noise"]) {
      std::cout << prefix << name << "  " << level["noise_k"] << "  ";
      for (const char* key : kTableKeys) std::cout << level[key] << "  ";
      std::cout << "\n";
    }
}

// The pooled table first (method, k, figures), then one per family with the
// family's name in front.
void printTable(const nlohmann::json& report) {
  std::cout << "method   noise_k";
  for (const char* key : kTableKeys) std::cout << "  " << key;
  std::cout << "\n";
  printMethods("", report["methods"]);
  for (const auto& [family, r] : report["families"].items())
    printMethods(family + ": ", r["methods"]);
}

std::vector<sim::TerrainFamily> familiesOf(const std::vector<std::string>& names) {
  if (names.empty()) return {sim::kTerrainFamilies.begin(), sim::kTerrainFamilies.end()};
  std::vector<sim::TerrainFamily> families;
  for (const auto& n : names) {
    const auto f = sim::parseFamily(n);
    if (!f) throw CLI::ValidationError("--families", "unknown terrain family '" + n + "'");
    families.push_back(*f);
  }
  return families;
}

SensorPose parsePose(const std::string& text) {
  SensorPose p;
  char colon = 0;
  std::istringstream in(text);
  if (!(in >> p.height_m >> colon >> p.tilt_deg) || colon != ':' || !in.eof() ||
      !(p.height_m >= 0.5 && p.height_m <= 20) || !(p.tilt_deg >= 5 && p.tilt_deg <= 80))
    throw CLI::ValidationError("--poses", "'" + text +
                                              "' is not HEIGHT:TILT with a height of "
                                              "0.5-20 m and a tilt of 5-80 degrees");
  return p;
}

nlohmann::json evalElevation(const EvalElevationArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  const auto base = sim::readScannerModel(findResource("config/scanner.json"));
  const Box2 region = parseRegion(a.region);
  const auto families = familiesOf(a.families);
  std::vector<SensorPose> poses;
  for (const auto& p : a.poses) poses.push_back(parsePose(p));
  std::vector<std::uint64_t> seeds = a.seeds;
  if (seeds.empty() && a.tuning) seeds.assign(sim::kTuningSeeds.begin(), sim::kTuningSeeds.end());
  if (seeds.empty()) seeds.assign(sim::kEvaluationSeeds.begin(), sim::kEvaluationSeeds.end());
  const terrain::LocusOptions& options = a.locus;
  const auto grid = gridOver(region, a.resolution, "map");
  const auto regions = footholdRegions(region);
  const auto foot = footfall::readFootfallConfig(findResource("config/footfall.json")).foot;
  Scores pooled;
  nlohmann::json by_family = nlohmann::json::object();
  int scenes = 0;
  ProgressLine progress("eval elevation", families.size() * seeds.size() * poses.size());
  for (const auto family : families) {
    Scores scores;
    for (const auto seed : seeds)
      for (const auto& pose : poses) {
        std::ostringstream item;
        item << sim::familyName(family) << " seed " << seed << ", scanner " << pose.height_m
             << " m up, " << pose.tilt_deg << " deg down";
        progress.next(item.str());
        auto model = base;
        model.mount_height = pose.height_m;
        model.tilt = pose.tilt_deg * kDeg;
        const sim::CourseScene scene(sim::makeFamilyTerrain(family, seed), model);
        const auto truth = scene.truth(grid);
        for (const double k : a.noise_k) {
          auto noisy = model;
          noisy.range_sigma_k = k;
          const auto image = sim::simulateScan(scene.caster(), noisy, scene.sensorPose(), seed);
          auto locus = [&] { return terrain::buildLocusMap(image, grid, options); };
          auto binning = [&] { return terrain::buildBinnedMap(image, grid); };
          const auto by_locus = buildMap(locus, truth, regions, foot);
          const auto by_binning = buildMap(binning, truth, regions, foot);
          for (auto* s : {&scores, &pooled}) s->add(k, truth, by_locus, by_binning);
          ++scenes;
        }
      }
    by_family[std::string(sim::familyName(family))] = {{"methods", methodsJson(scores)}};
  }
  return {
      {"scenes", scenes},
      {"seeds", seeds},
      {"seed_set", a.seeds.empty() ? (a.tuning ? "tuning" : "evaluation") : "given"},
      {"noise_k", a.noise_k},
      {"poses", a.poses},
      {"region", a.region},
      {"resolution", a.resolution},
      {"threads", a.locus.threads},
      {"shadow_tolerance", "within_1_cell: one cell, 8-neighbourhood"},
      {"truth", "Embree on the terrain triangulated at 2 cm; scans by the project's ray caster"},
      {"min_grazing_deg", a.locus.edges.min_grazing_deg},
      {"step_ratio", a.locus.edges.step_ratio},
      {"edge_noise_sigmas", a.locus.edges.noise_sigmas},
      {"edge_weak_noise_sigmas", a.locus.edges.weak_noise_sigmas},
      {"grazing_oblique", a.locus.edges.mark_grazing},
      {"oblique_shadow_sides", a.locus.oblique_shadow_sides},
      {"grazing_noise_sigmas", a.locus.edges.grazing_noise_sigmas},
      {"grazing_weak_noise_sigmas", a.locus.edges.weak_grazing_noise_sigmas},
      {"grazing_weak_angle_deg", a.locus.edges.weak_grazing_deg},
      {"grazing_concave_turn_deg", a.locus.edges.concave_turn_deg},
      {"grazing_baseline_rows", a.locus.edges.grazing_baseline_rows},
      {"grazing_baseline_noise_sigmas", a.locus.edges.grazing_baseline_noise_sigmas},
      {"max_sample_spacing_m", a.locus.max_sample_spacing_m},
      {"max_gap_hidden_by_noise_m", a.locus.max_gap_hidden_by_noise_m},
      {"curved_between_scanlines", a.locus.curved_between_scanlines},
      {"face_side_noise_sigmas", a.locus.face_side_noise_sigmas},
      {"undecided_before_shadow_steps", a.locus.undecided_before_shadow},
      {"undecided_shadow_far_end_share", a.locus.undecided_shadow_far_end},
      {"crest_max_angle_deg", a.locus.crest_max_angle_deg},
      {"methods", methodsJson(pooled)},
      {"families", by_family},
      {"elapsed_ms", millisecondsSince(start)}};
}

}  // namespace

void addEval(CLI::App& app) {
  auto* eval = app.add_subcommand("eval", "Measure the algorithms against simulator ground truth");
  eval->require_subcommand(1);
  auto args = std::make_shared<EvalElevationArgs>();
  auto* cmd = eval->add_subcommand(
      "elevation",
      "Locus method vs Cartesian binning on simulated scans of several terrain families");
  cmd->add_option("--families", args->families,
                  "terrain families (default: all): " + sim::familyNamesListed())
      ->delimiter(',');
  cmd->add_option("--seeds", args->seeds, "terrain seeds (default: the evaluation seeds)")
      ->delimiter(',');
  cmd->add_flag("--tuning", args->tuning, "use the tuning seeds instead of the evaluation seeds");
  cmd->add_option("--noise", args->noise_k, "range noise levels k [1/m]")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 0.01))
      ->capture_default_str();
  cmd->add_option("--poses", args->poses,
                  "scanner placements HEIGHT:TILT [m above the ground, degrees down]")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--region", args->region,
                  "map area XMIN,YMIN,XMAX,YMAX [m]; the rover stands at the origin facing +y")
      ->capture_default_str();
  cmd->add_option("--resolution", args->resolution, "map cell size [m]")
      ->check(CLI::Range(0.01, 1.0))
      ->capture_default_str();
  cmd->add_option("--threads", args->locus.threads, "threads for the locus method (timing)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  addLocusOptions(*cmd, args->locus);
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
