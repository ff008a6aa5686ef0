// Speed of the gait planner (one step: candidates, lookahead, leg recovery)
// and of its inner loop, the CSP margin. Run:
//   AMBLER_DATA_DIR=build/share/ambler build/bench/gait_bench
#include <benchmark/benchmark.h>

#include "core/Resources.h"
#include "footfall/FootfallConfig.h"
#include "gait/GaitPlanner.h"
#include "gait/RoverConfig.h"

namespace {

using namespace ambler;

gait::GaitContext context() {
  gait::GaitContext ctx = gait::readRoverConfig(findResource("config/rover.json"));
  ctx.footfall = footfall::readFootfallConfig(findResource("config/footfall.json"));
  return ctx;
}

// Rolling ground, 10 cm cells, every cell known.
terrain::ElevationMap rollingGround() {
  terrain::ElevationMap map(GridSpec::covering({-12, -12, 12, 30}, 0.1));
  for (int r = 0; r < map.grid().rows; ++r)
    for (int c = 0; c < map.grid().cols; ++c) {
      const auto p = map.grid().cellCenter(r, c);
      map.setKnown(r, c, 0.1 * std::sin(p.x() / 1.7) * std::cos(p.y() / 2.3), 0.01);
    }
  return map;
}

// Plans from the stances of a twelve-step walk, in turn.
void BM_PlanStep(benchmark::State& state) {
  const auto ctx = context();
  const auto map = rollingGround();
  std::vector<gait::Stance> stances{gait::nominalStance({{0, 0}, 0.0, 2.4}, ctx.model, ctx.gait)};
  for (int i = 0; i < 12; ++i)
    stances.push_back(gait::planStep(stances.back(), gait::Heading{}, map, ctx).after);
  std::size_t i = 0;
  for (auto _ : state) {
    auto plan = gait::planStep(stances[i++ % stances.size()], gait::Heading{}, map, ctx);
    benchmark::DoNotOptimize(plan);
  }
}
BENCHMARK(BM_PlanStep)->Unit(benchmark::kMillisecond);

void BM_ConservativeMargin(benchmark::State& state) {
  const std::vector<Eigen::Vector2d> feet{{-2.3, -1.2}, {-2.2, -0.2}, {-2.25, 0.8},
                                          {2.2, -0.7},  {2.3, 0.3},   {2.25, 1.3}};
  for (auto _ : state) benchmark::DoNotOptimize(gait::conservativeMargin(feet, {0.05, 0.1}));
}
BENCHMARK(BM_ConservativeMargin);

void BM_ConservativeSupportPolygon(benchmark::State& state) {
  const std::vector<Eigen::Vector2d> feet{{-2.3, -1.2}, {-2.2, -0.2}, {-2.25, 0.8},
                                          {2.2, -0.7},  {2.3, 0.3},   {2.25, 1.3}};
  for (auto _ : state)
    benchmark::DoNotOptimize(
        gait::stabilityMargin(gait::conservativeSupportPolygon(feet), {0.05, 0.1}));
}
BENCHMARK(BM_ConservativeSupportPolygon);

}  // namespace
