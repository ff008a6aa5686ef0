// The mission-log reader (missionlog::MissionLogReader, as replay and
// `ambler-cli log summary` open a log) on arbitrary files: a corrupt,
// truncated or foreign SQLite file, or one with the wrong schema or column
// types, must end in a LogError naming it, never a crash; each logged
// payload is then decoded as replay decodes it.
#include "FuzzSupport.h"
#include "link/Codec.h"
#include "missionlog/MissionLog.h"

using namespace ambler;

namespace {

std::vector<fuzz::Bytes> seeds() {
  const auto path = fuzz::scratchDir() / "seed.sqlite";
  {
    missionlog::MissionLog log(path, "fuzz seed");
    log.record(1.0, link::Telemetry{1, 1.0, link::BodyState{0.5, 1.0, 2.4, 0.1, false}});
    log.record(1.5, link::Telemetry{1, 1.5, link::LegState{2, {0.1, 1.2, 2.0}, true}});
    link::Command hold;
    hold.rover_id = 1, hold.operator_id = "alice", hold.sequence = 7, hold.body = link::Hold{};
    log.record(2.0, hold);
    log.record(missionlog::Decision{2.5, "alice", 3, missionlog::Verdict::kApproved, "leg 2"});
    log.recordProduct(3.0, "task", R"({"name": "map", "kind": "perception"})");
  }
  return {fuzz::readBytes(path)};
}

void read(const std::filesystem::path& path) {
  const missionlog::MissionLogReader reader(path);
  (void)reader.summary();
  for (const auto& m : reader.messages(-INFINITY, INFINITY))
    fuzz::refusalOnly<link::DecodeError>([&] {
      if (m.direction == missionlog::Direction::kToRover)
        (void)link::decodeCommand(m.payload);
      else
        (void)link::decodeTelemetry(m.payload);
    });
  (void)reader.decisions();
  (void)reader.products();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  fuzz::seedCorpus(*argc, *argv, seeds);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // A fresh name each time: SQLite must not find the last input's -wal or
  // -shm beside this one.
  static unsigned n = 0;
  const auto path = fuzz::writeScratch("log-" + std::to_string(n++ % 2) + ".sqlite", data, size);
  for (const char* suffix : {"-wal", "-shm", "-journal"})
    std::filesystem::remove(path.string() + suffix);
  fuzz::refusalOnly<missionlog::LogError>([&] { read(path); });
  return 0;
}
