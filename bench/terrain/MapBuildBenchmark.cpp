// Elevation map construction from one simulated 256 x 256 range image of
// the obstacle course (seed 1, resources/config/scanner.json: k = 2e-4,
// 5 m high, tilted 30 deg) into a 20 m x 20 m map at 5 cm (400 x 400 =
// 160k cells) in front of the rover. Locus runs on one thread.
#include <benchmark/benchmark.h>

#include "core/Resources.h"
#include "sim/CourseScene.h"
#include "terrain/Binning.h"
#include "terrain/Locus.h"

namespace {

using namespace ambler;

struct Scene {
  sensor::RangeImage image;
  GridSpec grid = GridSpec::covering({-10.0, 3.0, 10.0, 23.0}, 0.05);

  Scene() {
    const sim::CourseScene course(1, sim::readScannerModel(findResource("config/scanner.json")));
    image = course.scan(1);
  }
};

const Scene& scene() {
  static const Scene s;
  return s;
}

void reportCells(benchmark::State& state, const terrain::ElevationMap& map) {
  state.counters["cells"] = map.grid().cellCount();
  state.counters["known"] = map.knownCount();
  state.counters["shadow"] = map.countOf(terrain::CellState::kShadow);
}

void BM_LocusMap(benchmark::State& state) {
  const auto& s = scene();
  terrain::LocusOptions options;
  options.threads = 1;
  terrain::ElevationMap map;
  for (auto _ : state) {
    map = terrain::buildLocusMap(s.image, s.grid, options);
    benchmark::DoNotOptimize(map);
  }
  reportCells(state, map);
}
BENCHMARK(BM_LocusMap)->Unit(benchmark::kMillisecond);

void BM_BinnedMap(benchmark::State& state) {
  const auto& s = scene();
  terrain::ElevationMap map;
  for (auto _ : state) {
    map = terrain::buildBinnedMap(s.image, s.grid);
    benchmark::DoNotOptimize(map);
  }
  reportCells(state, map);
}
BENCHMARK(BM_BinnedMap)->Unit(benchmark::kMillisecond);

void BM_OccludingEdges(benchmark::State& state) {
  const auto& s = scene();
  for (auto _ : state) {
    terrain::OccludingEdges edges(s.image);
    benchmark::DoNotOptimize(edges);
  }
}
BENCHMARK(BM_OccludingEdges)->Unit(benchmark::kMillisecond);

}  // namespace
