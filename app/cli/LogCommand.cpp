// ambler-cli log summary: what a mission log holds (docs/formats.md,
// "Mission log").
#include <memory>

#include "cli/Arguments.h"
#include "cli/Commands.h"
#include "missionlog/MissionLog.h"

namespace ambler::cli {

namespace {

struct LogSummaryArgs {
  std::string file;
  bool json = false;
};

nlohmann::json summaryJson(const std::string& file, const missionlog::Summary& s) {
  return {{"file", file},
          {"mission", s.mission},
          {"messages", s.messages},
          {"from_rover", s.from_rover},
          {"to_rover", s.to_rover},
          {"first_s", s.messages > 0 ? nlohmann::json(s.first_s) : nlohmann::json()},
          {"duration_s", s.durationS()},
          {"steps_approved", s.approved},
          {"steps_rejected", s.rejected},
          {"steps_edited", s.edited},
          {"products", s.products}};
}

}  // namespace

void addLog(CLI::App& app) {
  auto* log = app.add_subcommand("log", "Inspect mission logs");
  log->require_subcommand(1);
  auto args = std::make_shared<LogSummaryArgs>();
  auto* summary = log->add_subcommand(
      "summary", "Counts by message type, duration, steps approved / rejected / edited");
  summary->add_option("file", args->file, "mission log (SQLite)")->required();
  summary->add_flag("--json", args->json,
                    "print JSON (the only output format; accepted for symmetry with eval)");
  summary->callback([args] {
    const missionlog::MissionLogReader reader(args->file);
    printJson(summaryJson(args->file, reader.summary()));
  });
}

}  // namespace ambler::cli
