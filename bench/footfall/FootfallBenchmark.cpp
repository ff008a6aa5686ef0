// Footfall evaluation over a 4 m x 4 m region of the obstacle course (seed
// 1) at 2 cm (200 x 200 = 40k candidate feet) with the 30 cm foot: all five
// criteria of krotkov1989 §4 from one pass, and each criterion alone. The
// map is the simulator's exact ground with sigma = 1 cm; one core.
#include <benchmark/benchmark.h>

#include "core/Resources.h"
#include "footfall/Criteria.h"
#include "sim/CourseScene.h"

namespace {

using namespace ambler;

struct Scene {
  terrain::ElevationMap map;
  Box2 region{-2.0, 8.0, 2.0, 12.0};

  Scene() {
    const sim::CourseScene course(1, sim::readScannerModel(findResource("config/scanner.json")));
    // The region and a foot's radius around it.
    map = terrain::ElevationMap(GridSpec::covering({-2.2, 7.8, 2.2, 12.2}, 0.02));
    for (int r = 0; r < map.grid().rows; ++r)
      for (int c = 0; c < map.grid().cols; ++c) {
        const auto p = map.grid().cellCenter(r, c);
        map.setKnown(r, c, course.terrain().height(p.x(), p.y()), 0.01);
      }
  }
};

const Scene& scene() {
  static const Scene s;
  return s;
}

void BM_AllFiveCriteria(benchmark::State& state) {
  const auto& s = scene();
  std::vector<footfall::ScoreMap> maps;
  for (auto _ : state) {
    maps = footfall::evaluateAllCriteria(s.map, s.region);
    benchmark::DoNotOptimize(maps);
  }
  state.counters["candidates"] = maps.front().grid.cellCount();
  state.counters["valid"] = maps.front().validCount();
}
BENCHMARK(BM_AllFiveCriteria)->Unit(benchmark::kMillisecond);

void BM_OneCriterion(benchmark::State& state) {
  const auto& s = scene();
  const auto criterion = footfall::kAllCriteria[state.range(0)];
  state.SetLabel(std::string(footfall::criterionName(criterion)));
  for (auto _ : state) {
    auto map = footfall::evaluateFootfalls(s.map, s.region, criterion);
    benchmark::DoNotOptimize(map);
  }
}
BENCHMARK(BM_OneCriterion)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);

}  // namespace
