// ambler-cli keygen: a new operator key (docs/dds.md, "Signing keys").
#include <memory>

#include "cli/Arguments.h"
#include "cli/Commands.h"
#include "link/Signing.h"

namespace ambler::cli {

void addKeygen(CLI::App& app) {
  struct Args {
    std::string operator_id, out;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "keygen",
      "Make an operator's signing key: the console's key file (owner-only) and, on stdout, the "
      "entry for the rover's operators file");
  cmd->add_option("--operator", args->operator_id, "operator id (no spaces)")->required();
  cmd->add_option("--out", args->out, "console key file to create (never replaced)")->required();
  cmd->callback([args] {
    const auto key = link::newOperatorKey(args->operator_id);
    link::writeOperatorKey(args->out, key);
    printJson({{"key_file", args->out},
               {"operator", key.operator_id},
               {"rover_entry", {{"operator", key.operator_id}, {"key_hex", link::keyHex(key)}}},
               {"next", "add rover_entry to the rover's operators file's \"operators\" list"}});
  });
}

}  // namespace ambler::cli
