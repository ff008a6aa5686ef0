#pragma once

#include <CLI/CLI.hpp>

namespace ambler::cli {

// Each adds its subcommand to `app`; the subcommand prints JSON on stdout
// and throws on failure (main turns that into a message and exit code 1).
void addSimScan(CLI::App& app);
void addSimStriper(CLI::App& app);
void addInfo(CLI::App& app);

}  // namespace ambler::cli
