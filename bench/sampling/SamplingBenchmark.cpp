// Superquadric fits of 2,000 points (target <= 10 ms), and the other
// stages of rock sampling on one simulated striper image.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <cmath>
#include <optional>
#include <random>

#include "sampling/RockSampler.h"
#include "sim/ObstacleCourse.h"
#include "sim/StriperSim.h"

namespace {

using namespace ambler;

// 2,000 points on the upper two thirds of a rock, 0.5 mm noise (what the
// striper sees of a rock on the sand).
std::vector<Eigen::Vector3d> rockTop() {
  Superquadric s;
  s.size = {0.06, 0.04, 0.03};
  s.eps1 = 0.6;
  s.eps2 = 0.8;
  s.pose = Eigen::Translation3d(0.1, -0.2, 0.02) * Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ());
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0.0, 0.0005);
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < 40; ++i)
    for (int k = 0; k < 50; ++k) {
      const double eta = -M_PI / 6 + (M_PI / 2 + M_PI / 6) * (i + 0.5) / 40;
      const double omega = -M_PI + 2 * M_PI * (k + 0.5) / 50;
      out.push_back(s.surfacePoint(eta, omega) +
                    Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
    }
  return out;
}

void BM_FitSuperquadric(benchmark::State& state) {
  const auto points = rockTop();
  sampling::FitOptions options;
  options.robust = state.range(0) != 0;
  options.residual =
      state.range(1) != 0 ? sampling::FitResidual::kSolina : sampling::FitResidual::kRadial;
  // The sand where the points end, for the prior that the rock rests on it.
  std::optional<Eigen::Hyperplane<double, 3>> sand;
  if (state.range(2) != 0) sand = Eigen::Hyperplane<double, 3>(Eigen::Vector3d::UnitZ(), 0.0);
  int iterations = 0;
  for (auto _ : state) {
    const auto fit = sampling::fitSuperquadric(points, options, sand);
    iterations = fit.iterations;
    benchmark::DoNotOptimize(fit);
  }
  state.counters["points"] = double(points.size());
  state.counters["lm_iterations"] = iterations;
}
// {robust, Solina's residual, resting prior}
BENCHMARK(BM_FitSuperquadric)
    ->Args({0, 0, 0})
    ->Args({1, 0, 0})
    ->Args({1, 0, 1})
    ->Args({0, 1, 0})
    ->Unit(benchmark::kMillisecond);

const sim::StriperScene& scene() {
  static const sim::ProceduralTerrain terrain(sim::makeWorkArea({.seed = 3}));
  static const auto s = sim::simulateStriper(terrain, sim::StriperModel{}, 3);
  return s;
}

void BM_Features(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(sampling::extractFeatures(scene().image));
}
BENCHMARK(BM_Features)->Unit(benchmark::kMillisecond);

void BM_AutoSeedsAndContours(benchmark::State& state) {
  const auto features = sampling::extractFeatures(scene().image);
  for (auto _ : state) {
    for (const auto& seed : sampling::automaticSeeds(scene().image, features))
      benchmark::DoNotOptimize(sampling::growContour(features, seed.pixel));
  }
}
BENCHMARK(BM_AutoSeedsAndContours)->Unit(benchmark::kMillisecond);

}  // namespace
