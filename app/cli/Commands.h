#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gait/Stance.h"
#include "terrain/Locus.h"

namespace ambler::cli {

// Each adds its subcommand to `app`; the subcommand prints JSON on stdout
// and throws on failure (main turns that into a message and exit code 1).
void addSimScan(CLI::App& app);
void addSimStriper(CLI::App& app);
void addSimCamera(CLI::App& app);
void addSimPairs(CLI::App& app);
void addInfo(CLI::App& app);
void addMap(CLI::App& app);
void addEval(CLI::App& app);
void addFootfall(CLI::App& app);
void addWalk(CLI::App& app);
void addLog(CLI::App& app);
void addDrive(CLI::App& app);
void addFitRock(CLI::App& app);
void addRegister(CLI::App& app);
void addDanger(CLI::App& app);
void addMesh(CLI::App& app);
void addPath(CLI::App& app);
void addKeygen(CLI::App& app);
// One evaluation at its default options, as `eval all` runs it.
struct Evaluation {
  std::string name;
  std::function<nlohmann::json()> run;
};
using Evaluations = std::vector<Evaluation>;

// The `eval` subcommands besides `elevation` and `all`; each also adds
// itself to `all`.
void addEvalLink(CLI::App& eval, Evaluations& all);
void addEvalRocks(CLI::App& eval, Evaluations& all);
void addEvalMapping(CLI::App& eval, Evaluations& all);
void addEvalDem(CLI::App& eval, Evaluations& all);
void addEvalDanger(CLI::App& eval, Evaluations& all);
void addEvalWalk(CLI::App& eval, Evaluations& all);
// `eval all`: runs every evaluation in `all`.
void addEvalAll(CLI::App& eval, std::shared_ptr<const Evaluations> all);

// The locus map's options shared by `map` and `eval elevation`: occluding
// edges and the sample spacing beyond which cells are unknown.
void addLocusOptions(CLI::App& cmd, terrain::LocusOptions& locus);

// The path a walk follows, shared by `walk` and `drive`: an arc of
// --radius (finite, not 0), a turn in place (--turn left|right), or
// straight without either.
struct WalkPath {
  double radius_m = 0.0;  // 0: straight
  std::string turn;       // "left", "right" or empty
  gait::Heading heading() const;
};
void addWalkPathOptions(CLI::App& cmd, WalkPath& path);

}  // namespace ambler::cli
