// ambler-cli: the ground station's algorithms for batch work, evaluation and
// benchmarks. Every subcommand reads and writes the files of docs/formats.md
// and prints JSON.
#include <iostream>

#include "cli/Commands.h"
#include "core/Memory.h"
#include "core/Resources.h"

int main(int argc, char** argv) {
  ambler::keepFreedMemoryForReuse();  // before the first scan's buffers
  ambler::adviseHugePagesForTheHeap();
  CLI::App app{
      "Ambler ground station: batch tool (simulation, mapping, footfalls, evaluation, file "
      "inspection, mission logs, a headless console)"};
  // The data line says which configuration the program reads: an installed
  // package's, the build tree's or $AMBLER_DATA_DIR.
  app.set_version_flag("--version", [] {
    std::string data;
    try {
      data = ambler::findResource("config/rover.json").parent_path().parent_path().string();
    } catch (const std::exception&) {
      data = "not found";
    }
    return std::string("ambler-cli ") + AMBLER_VERSION + "\ndata: " + data;
  });
  app.require_subcommand(1);
  ambler::cli::addSimScan(app);
  ambler::cli::addSimStriper(app);
  ambler::cli::addSimCamera(app);
  ambler::cli::addSimPairs(app);
  ambler::cli::addInfo(app);
  ambler::cli::addMap(app);
  ambler::cli::addEval(app);
  ambler::cli::addFootfall(app);
  ambler::cli::addWalk(app);
  ambler::cli::addLog(app);
  ambler::cli::addDrive(app);
  ambler::cli::addFitRock(app);
  ambler::cli::addRegister(app);
  ambler::cli::addDanger(app);
  ambler::cli::addMesh(app);
  ambler::cli::addPath(app);
  ambler::cli::addKeygen(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::cerr << "ambler-cli: error: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}
