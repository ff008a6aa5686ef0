// ambler-cli footfall: score maps of the footfall criteria (krotkov1989 §4)
// or the gait planner's composite cost map (cmu-1990) over a region of an
// elevation map, and the best foothold.
#include <filesystem>
#include <memory>

#include "cli/Arguments.h"
#include "cli/Commands.h"
#include "core/Resources.h"
#include "footfall/CostMaps.h"
#include "footfall/FootfallConfig.h"
#include "io/Json.h"
#include "terrain/ElevationMapFile.h"
#include "terrain/Queries.h"

namespace ambler::cli {

namespace {

namespace fs = std::filesystem;

struct FootfallArgs {
  std::string map;
  std::string region;
  std::string criterion = "equilibrium";
  std::string out;
  std::string config;
  std::string leg;
  double heading_deg = 90.0;
  std::string reference_z;
  std::string scanner;
};

nlohmann::json footholdJson(const footfall::Foothold& f) {
  if (!f.found) return {{"found", false}};
  return {{"found", true}, {"x", f.x}, {"y", f.y}, {"score", f.score}};
}

// Composite costs need the leg: its shaft (default: the region's centre
// minus the mean reach along the heading), the heading, the height the
// elevation limits refer to (default: the mean known height in the
// region) and, for the visibility cost, the scanner.
footfall::LegContext legFrom(const FootfallArgs& a, const terrain::ElevationMap& map,
                             const Box2& region, const footfall::CostMapOptions& o) {
  footfall::LegContext leg;
  leg.heading_rad = a.heading_deg * M_PI / 180;
  const Eigen::Vector2d heading(std::cos(leg.heading_rad), std::sin(leg.heading_rad));
  const Eigen::Vector2d centre((region.x_min + region.x_max) / 2,
                               (region.y_min + region.y_max) / 2);
  leg.shaft = centre - heading * (o.limits.reach_min_m + o.limits.reach_max_m) / 2;
  if (!a.leg.empty()) {
    const auto v = parseNumbers(a.leg, 2, "--leg", "X,Y");
    leg.shaft = {v[0], v[1]};
  }
  if (!a.reference_z.empty()) {
    leg.reference_z = parseNumbers(a.reference_z, 1, "--reference-z", "a height in metres")[0];
  } else {
    const auto summary = terrain::summarize(map, region);
    if (summary.withHeight() == 0)
      throw std::invalid_argument("region has no cell with a height to take --reference-z from");
    leg.reference_z = summary.mean_z;
  }
  if (!a.scanner.empty()) {
    const auto v = parseNumbers(a.scanner, 4, "--scanner", "X,Y,HEADING_DEG,HFOV_DEG");
    if (!(v[3] > 0 && v[3] <= 360))
      throw std::invalid_argument("--scanner field of view must be in (0, 360] degrees");
    leg.scanner = footfall::ScannerView{{v[0], v[1]}, v[2] * M_PI / 180, v[3] * M_PI / 180};
  }
  return leg;
}

void runFootfall(const FootfallArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  const auto map = terrain::readElevationMap(a.map);
  const Box2 region = parseRegion(a.region);
  const auto options = footfall::readFootfallConfig(
      a.config.empty() ? findResource("config/footfall.json") : fs::path(a.config));
  fs::create_directories(a.out);
  nlohmann::json result = {{"criterion", a.criterion}};
  const auto eval_start = std::chrono::steady_clock::now();
  footfall::ScoreMap score;
  if (a.criterion == "composite") {
    const auto leg = legFrom(a, map, region, options);
    const auto costs = footfall::buildCostMaps(map, region, leg, options);
    for (const auto* m : {&costs.roughness, &costs.slope, &costs.body_advance, &costs.visibility})
      terrain::writeLayer(m->score, m->grid, fs::path(a.out) / (m->name + ".tif"), m->unit);
    score = costs.composite;
    result["leg"] = {{"shaft", {leg.shaft.x(), leg.shaft.y()}},
                     {"heading_deg", a.heading_deg},
                     {"reference_z", leg.reference_z},
                     {"visibility", leg.scanner.has_value()}};
  } else {
    score = footfall::evaluateFootfalls(map, region, *footfall::criterionFromName(a.criterion),
                                        options.foot);
  }
  const double eval_ms = millisecondsSince(eval_start);
  terrain::writeLayer(score.score, score.grid, fs::path(a.out) / "score.tif", score.unit);
  nlohmann::json header = io::gridJson(score.grid);
  header["criterion"] = a.criterion;
  header["unit"] = score.unit;
  header["no_data"] = "NaN: the foot cannot stand there";
  const auto best = footfall::bestFoothold(score);
  header["best"] = footholdJson(best);
  io::writeJsonFile(fs::path(a.out) / "footfall.json", header);
  result["unit"] = score.unit;
  result["best"] = footholdJson(best);
  result["candidates"] = score.grid.cellCount();
  result["valid"] = score.validCount();
  result["out"] = a.out;
  result["evaluate_ms"] = eval_ms;
  result["elapsed_ms"] = millisecondsSince(start);
  printJson(result);
}

}  // namespace

void addFootfall(CLI::App& app) {
  auto args = std::make_shared<FootfallArgs>();
  auto* cmd = app.add_subcommand(
      "footfall", "Score footholds in a region of an elevation map and print the best one");
  cmd->add_option("--map", args->map, "elevation map folder (docs/formats.md)")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--region", args->region, "candidate foot centres XMIN,YMIN,XMAX,YMAX [m]")
      ->required();
  cmd->add_option("--criterion", args->criterion,
                  "maxmin, planar, support, freevolume, equilibrium (krotkov1989 §4) or "
                  "composite (cmu-1990 cost maps)")
      ->check(
          CLI::IsMember({"maxmin", "planar", "support", "freevolume", "equilibrium", "composite"}))
      ->capture_default_str();
  cmd->add_option("--out", args->out, "output folder: score.tif and footfall.json")->required();
  cmd->add_option("--config", args->config,
                  "foot, limits and weights (default: resources/config/footfall.json)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--leg", args->leg, "composite: the leg's shaft X,Y [m]");
  cmd->add_option("--heading", args->heading_deg, "composite: direction of body advance [deg]")
      ->check(CLI::Range(-360.0, 360.0))
      ->capture_default_str();
  cmd->add_option("--reference-z", args->reference_z,
                  "composite: height the elevation limits refer to [m] (default: mean of the "
                  "region)");
  cmd->add_option("--scanner", args->scanner,
                  "composite: scanner X,Y,HEADING_DEG,HFOV_DEG for the visibility cost");
  cmd->callback([args] { runFootfall(*args); });
}

}  // namespace ambler::cli
