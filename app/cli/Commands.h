#pragma once

#include <CLI/CLI.hpp>

#include "terrain/OccludingEdges.h"

namespace ambler::cli {

// Each adds its subcommand to `app`; the subcommand prints JSON on stdout
// and throws on failure (main turns that into a message and exit code 1).
void addSimScan(CLI::App& app);
void addSimStriper(CLI::App& app);
void addSimCamera(CLI::App& app);
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
// `eval link`, `eval rocks` and `eval mapping`, under the `eval` subcommand.
void addEvalLink(CLI::App& eval);
void addEvalRocks(CLI::App& eval);
void addEvalMapping(CLI::App& eval);
void addEvalDem(CLI::App& eval);
void addEvalDanger(CLI::App& eval);

// The occluding-edge options shared by `map` and `eval elevation`.
void addEdgeOptions(CLI::App& cmd, terrain::OccludingEdgeOptions& edges);

}  // namespace ambler::cli
