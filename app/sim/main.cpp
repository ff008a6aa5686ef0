// ambler-sim: the simulated Ambler served over DDS, for a ground station in
// another process or on another host (docs/formats.md, "Link messages").
// Verifies every command with the operators' keys, executes it on the
// obstacle course (or a terrain family's ground, or a terrain model) and
// publishes acks, leg and body states, range images and a heartbeat.
#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/Memory.h"
#include "link/dds/DdsMessages.h"
#include "rover/RoverLoop.h"
#include "rover/SimulatedGround.h"

namespace {

std::atomic<bool> g_stop{false};

void onSignal(int) { g_stop = true; }

std::vector<std::string> familyNames() {
  std::vector<std::string> names;
  for (const auto f : ambler::sim::kTerrainFamilies) names.emplace_back(ambler::sim::familyName(f));
  return names;
}

struct Args {
  std::uint32_t domain = 0;
  std::uint32_t rover_id = 1;
  std::uint64_t seed = 1;
  std::string keys;
  int heartbeat_ms = 1000;
  double link_timeout_s = 3.0;
  double time_scale = 0.0;
  double duration_s = 0.0;
  std::string family = "course";
  std::string dtm;
  std::vector<double> dtm_centre;  // empty: the raster's centre
  double dtm_size = 60.0;
  double dtm_resolution = 0.1;
};

void run(const Args& a) {
  using namespace ambler;
  // Before the course is built: a console may sign its first command while
  // it is.
  const double started_s = link::utcNowS();
  const auto config = rover::readInstalledSimulatedRoverConfig();
  rover::SimulatedRoverOptions options;
  options.rover_id = a.rover_id;
  options.link_timeout_s = a.link_timeout_s;
  options.time_scale = a.time_scale;
  options.started_s = started_s;
  rover::SimulatedGround ground;
  ground.family = *sim::parseFamily(a.family);  // checked against the families' names
  if (!a.dtm.empty()) {
    ground.dtm = sim::DtmSource{
        a.dtm, {.width = a.dtm_size, .height = a.dtm_size, .resolution = a.dtm_resolution}};
    if (a.dtm_centre.size() == 2)
      ground.dtm->window.centre = Eigen::Vector2d(a.dtm_centre[0], a.dtm_centre[1]);
  }
  ground.applyTo(a.seed, options);
  if (!a.keys.empty()) options.operators = link::readOperatorKeys(a.keys);
  rover::SimulatedRover rover(config, options);
  link::dds::RoverEndpoint endpoint(a.domain, a.rover_id);

  long commands = 0, refused = 0;
  // What was carried out, by type: a command executed twice would show.
  std::map<std::pair<std::string, std::uint64_t>, std::string> received;
  std::map<std::string, long> executed;
  const auto start = std::chrono::steady_clock::now();
  rover::RoverLoopIo io;
  io.receive = [&](std::chrono::milliseconds timeout) {
    std::vector<rover::Incoming> in;
    for (auto& r : endpoint.takeCommands(std::min(timeout, std::chrono::milliseconds(100)))) {
      // Heartbeats are answered only when refused.
      const auto& c = r.command;
      if (!std::holds_alternative<link::GroundHeartbeat>(c.body))
        received[{link::consoleName(c.operator_id, c.console_id), c.sequence}] =
            link::typeName(c.body);
      in.push_back({std::move(r.command), std::move(r.malformed)});
    }
    commands += long(in.size());
    return in;
  };
  io.publish = [&](const link::Telemetry& t) {
    if (const auto* ack = std::get_if<link::CommandAck>(&t.body)) {
      const auto it =
          received.find({link::consoleName(ack->operator_id, ack->console_id), ack->sequence});
      if (!ack->accepted)
        ++refused;
      else if (it != received.end())
        ++executed[it->second];
      if (it != received.end()) received.erase(it);
    }
    endpoint.publish(t);
  };
  io.note = [](const std::string& what) {
    std::cout << nlohmann::json{{"rover_log", what}, {"utc_s", link::utcNowS()}} << std::endl;
  };
  io.stopping = [&] {
    return g_stop.load() ||
           (a.duration_s > 0 &&
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >
                a.duration_s);
  };
  std::cout << nlohmann::json{{"ambler_sim", "ready"},
                              {"domain", a.domain},
                              {"rover_id", a.rover_id},
                              {"seed", a.seed},
                              {"terrain", a.dtm.empty() ? a.family : a.dtm},
                              {"link_timeout_s", a.link_timeout_s},
                              {"time_scale", a.time_scale},
                              {"operators", options.operators.size()}}
            << std::endl;
  rover::runRoverLoop(rover, std::chrono::milliseconds(a.heartbeat_ms), io);
  std::cout << nlohmann::json{{"ambler_sim", "stopped"},
                              {"commands", commands},
                              {"refused", refused},
                              {"executed", executed}}
            << std::endl;
}

}  // namespace

int main(int argc, char** argv) {
  ambler::keepFreedMemoryForReuse();  // before the first scan's buffers
  ambler::adviseHugePagesForTheHeap();
  CLI::App app{"Ambler simulator served over DDS (loopback; see docs/formats.md)"};
  app.set_version_flag("--version", std::string("ambler-sim ") + AMBLER_VERSION);
  Args a;
  app.add_option("--domain", a.domain, "DDS domain")
      ->check(CLI::Range(0, 232))
      ->capture_default_str();
  app.add_option("--rover-id", a.rover_id, "this rover's id (the topics' key)")
      ->capture_default_str();
  app.add_option(
         "--seed", a.seed,
         "seed of the ground (obstacle course or --family terrain) and of the execution noise")
      ->capture_default_str();
  auto* family =
      app.add_option("--family", a.family,
                     "walk on a terrain family drawn from the seed, as the evaluations draw it")
          ->check(CLI::IsMember(familyNames()))
          ->capture_default_str();
  app.add_option("--dtm", a.dtm,
                 "walk on a real terrain model instead of the course: any DTM GDAL reads "
                 "(GeoTIFF, PDS3/PDS4, ISIS3), in a projected CRS")
      ->check(CLI::ExistingFile)
      ->excludes(family);
  app.add_option("--dtm-centre", a.dtm_centre,
                 "EASTING,NORTHING of the rover's start in the DTM's CRS [m] (default: the "
                 "raster's centre)")
      ->delimiter(',')
      ->expected(2);
  app.add_option("--dtm-size", a.dtm_size, "side of the square window loaded [m]")
      ->check(CLI::Range(5.0, 2000.0))
      ->capture_default_str();
  app.add_option("--dtm-resolution", a.dtm_resolution, "cell size it is resampled to [m]")
      ->check(CLI::Range(0.01, 10.0))
      ->capture_default_str();
  app.add_option("--keys", a.keys,
                 "operators' keys, {\"operators\": [{\"operator\", \"key_hex\"}]}; without it "
                 "every command is refused")
      ->check(CLI::ExistingFile);
  app.add_option("--heartbeat-ms", a.heartbeat_ms, "heartbeat period [ms]")
      ->check(CLI::Range(10, 60000))
      ->capture_default_str();
  app.add_option("--link-timeout", a.link_timeout_s,
                 "hold (refuse motion until Resume) when no signed command or GroundHeartbeat has "
                 "come for this long [s]; 0: never")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  app.add_option("--time-scale", a.time_scale,
                 "wall seconds per second of the rover model's motion: a move or scan is "
                 "acknowledged at once and reports its outcome this much of its modelled time "
                 "later (1: the Ambler's own speeds; 0: at once)")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  app.add_option("--duration", a.duration_s, "stop after this many seconds (0: at SIGINT/SIGTERM)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  try {
    app.parse(argc, argv);
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    run(a);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::cerr << "ambler-sim: error: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}
