// ambler-cli eval all: every evaluation at its defaults, one JSON object,
// with the headline figures next to the papers' where they report one.
#include <iostream>
#include <memory>
#include <set>
#include <stdexcept>

#include "cli/Arguments.h"
#include "cli/Commands.h"

namespace ambler::cli {

namespace {

struct EvalAllArgs {
  std::vector<std::string> only, skip;
  bool json = true;  // the only output form
};

// One figure of the summary: where it is in the reports, and what the
// papers say about the same quantity (null where they give no number).
struct Headline {
  const char* what;
  const char* pointer;  // JSON pointer into the combined report
  const char* unit;
  const char* paper;
};

// The papers report few numbers; these are all of those that measure the
// same thing as an evaluation here.
const Headline kHeadlines[] = {
    {"elevation RMSE, locus method (six terrain families, all noise levels)",
     "/elevation/methods/locus/rmse_m", "m", nullptr},
    {"elevation RMSE, Cartesian binning", "/elevation/methods/binning/rmse_m", "m", nullptr},
    {"elevation RMSE on the cells both methods know, locus",
     "/elevation/methods/locus/rmse_on_shared_cells_m", "m", nullptr},
    {"elevation RMSE on the cells both methods know, binning",
     "/elevation/methods/binning/rmse_on_shared_cells_m", "m", nullptr},
    {"elevation coverage of visible cells, locus", "/elevation/methods/locus/coverage", "",
     nullptr},
    {"range-shadow recall within one cell, locus",
     "/elevation/methods/locus/shadow_recall_within_1_cell", "", nullptr},
    {"range-shadow precision within one cell, locus",
     "/elevation/methods/locus/shadow_precision_within_1_cell", "", nullptr},
    {"share of the range shadow that lies out of view, locus",
     "/elevation/methods/locus/shadow_out_of_view", "", nullptr},
    {"occluded cells reported known, locus", "/elevation/methods/locus/occluded_known", "",
     nullptr},
    {"sigma calibration (std of error / sigma), locus",
     "/elevation/methods/locus/sigma_calibration", "", nullptr},
    {"sigma calibration over the truly visible cells, locus",
     "/elevation/methods/locus/sigma_calibration_visible", "", nullptr},
    {"locus map 20 x 20 m at 5 cm, one core", "/elevation/methods/locus/ms_per_map", "ms", nullptr},
    {"wall time saved by planning while executing (median of 5 comparisons)",
     "/walk/wall_saving_pct/median", "%", "over 30 % (cmu-1990, Task Control)"},
    {"walking speed while moving", "/walk/speed_while_moving_m_per_min", "m/min",
     "0.35 m/min overall, 75 % of it moving: 0.47 m/min (cmu-1990, fig. 6); design: 1 m/min"},
    {"position error at the end of a 100-step walk, dead reckoning alone (median of 10)",
     "/walk/dead_reckoning_error_final_m/median", "m",
     "typically within 1-2 cm per move (cmu-1990, Real-Time Control)"},
    {"position error at the end of a 100-step walk, with registration (median of 10)",
     "/walk/pose_error_final_m/median", "m",
     "iconic matching of terrain maps 'to augment dead-reckoning' (cmu-1990, Perception)"},
    {"CSP violations in 10 x 100 steps", "/walk/csp_violations", "",
     "the 1990 NASA demo: some 25 autonomous steps over sand, boulders, a ramp and out of a "
     "1 m trench"},
    {"one gait planning step (median)", "/walk/plan_ms_median/median", "ms", nullptr},
    {"signed command round trip, p99", "/link/round_trip_ms/p99", "ms", nullptr},
    {"range images through DDS", "/link/range_images_per_s", "1/s",
     "scanner: 2 images/s (cmu-1990, Perception)"},
    {"rocks found by automatic seeds", "/rocks/resting/auto_seed_recall", "", nullptr},
    {"contour IoU from a click (median)", "/rocks/resting/contour_iou/median", "", nullptr},
    {"superquadric centre error, robust fit (median)", "/rocks/resting/robust/center_err_mm/median",
     "mm", nullptr},
    {"superquadric size error, robust fit (median)", "/rocks/resting/robust/size_err_pct/median",
     "%", nullptr},
    {"ICP translation error (median)", "/mapping/icp_trans_err_pct_of_distance/median",
     "% of distance", "under 1 % of distance travelled (bakambu, conclusion)"},
    {"ICP translation error (max)", "/mapping/icp_trans_err_pct_of_distance/max", "% of distance",
     nullptr},
    {"global localization in a 1 m model, success", "/mapping/global_loc_success_rate", "",
     nullptr},
    {"global localization time (max)", "/mapping/global_loc_s/max", "s",
     "30 s to 2 min on a 1.8 GHz Pentium 4 (bakambu, Mars Yard localization)"},
    {"path across a view's mesh (median)", "/mapping/path_ms/median", "ms", nullptr},
    {"USGS DEM windows localized", "/dem/global_loc/success_rate", "", nullptr},
    {"danger map: recall of rough pixels (median)", "/danger/recall/median", "", nullptr},
    {"danger map: precision (median)", "/danger/precision/median", "", nullptr},
    {"danger map, route and plan of a 640 x 480 image (median)", "/danger/ms/median", "ms",
     nullptr},
};

nlohmann::json headlines(const nlohmann::json& report) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& h : kHeadlines) {
    const nlohmann::json::json_pointer at(h.pointer);
    rows.push_back({{"what", h.what},
                    {"measured", report.contains(at) ? report.at(at) : nlohmann::json()},
                    {"unit", h.unit},
                    {"paper", h.paper ? nlohmann::json(h.paper) : nlohmann::json()},
                    {"from", h.pointer}});
  }
  return rows;
}

bool selected(const EvalAllArgs& a, const std::string& name) {
  const auto listed = [&](const std::vector<std::string>& names) {
    return std::find(names.begin(), names.end(), name) != names.end();
  };
  return (a.only.empty() || listed(a.only)) && !listed(a.skip);
}

// Runs each selected evaluation in turn, progress on stderr. A failing one
// is reported in its place and the rest still run; the command fails at the
// end, after printing what was measured.
void runEvalAll(const EvalAllArgs& a, const Evaluations& all) {
  nlohmann::json report = nlohmann::json::object();
  std::vector<std::string> failed;
  const auto start = std::chrono::steady_clock::now();
  std::size_t n = 0, count = 0;
  for (const auto& e : all) count += selected(a, e.name);
  for (const auto& e : all) {
    if (!selected(a, e.name)) continue;
    std::cerr << "eval all: [" << ++n << "/" << count << "] " << e.name << " ..." << std::flush;
    const auto began = std::chrono::steady_clock::now();
    try {
      const ProgressLine::Quiet quiet;
      report[e.name] = e.run();
      std::cerr << " " << millisecondsSince(began) / 1000 << " s\n";
    } catch (const std::exception& error) {
      report[e.name] = {{"error", error.what()}};
      failed.push_back(e.name);
      std::cerr << " failed: " << error.what() << "\n";
    }
  }
  report["summary"] = headlines(report);
  report["elapsed_s"] = millisecondsSince(start) / 1000;
  printJson(report);
  if (!failed.empty()) {
    std::string names;
    for (const auto& f : failed) names += (names.empty() ? "" : ", ") + f;
    throw std::runtime_error("eval all: failed: " + names);
  }
}

}  // namespace

void addEvalAll(CLI::App& eval, std::shared_ptr<const Evaluations> all) {
  auto args = std::make_shared<EvalAllArgs>();
  std::set<std::string> names;
  for (const auto& e : *all) names.insert(e.name);
  auto* cmd = eval.add_subcommand(
      "all",
      "Every evaluation at its defaults in one JSON object, with a summary of the "
      "headline figures next to the papers' (several minutes)");
  cmd->add_option("--only", args->only, "run only these evaluations")
      ->delimiter(',')
      ->check(CLI::IsMember(names));
  cmd->add_option("--skip", args->skip, "leave these evaluations out")
      ->delimiter(',')
      ->check(CLI::IsMember(names));
  cmd->add_flag("--json", args->json, "print JSON (the only output form)");
  cmd->callback([args, all] { runEvalAll(*args, *all); });
}

}  // namespace ambler::cli
