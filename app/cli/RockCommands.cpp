// `eval rocks` and `fit-rock`: the rock-sampling pipeline (cmu-1990
// sampling paper) against simulated scenes, and on one striper folder.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <random>

#include "cli/Arguments.h"
#include "cli/Commands.h"
#include "sampling/RockSampler.h"
#include "sensor/StriperImageFile.h"
#include "sim/ObstacleCourse.h"
#include "sim/StriperSim.h"

namespace ambler::cli {

namespace {

struct Errors {
  std::vector<double> size_pct, center_mm, eps, ms;
};

struct MethodErrors {
  Errors clean, outliers;
};

struct Condition {
  int rocks = 0, seeded = 0, seeds = 0, false_seeds = 0;
  std::vector<double> iou;
  std::map<std::string, MethodErrors> methods;
};

// The largest relative error of the sizes [%], each true axis compared
// with the fitted axis nearest its direction (a fit may name the same
// shape's axes differently).
double sizeErrorPct(const Superquadric& fit, const Superquadric& truth) {
  return 100 * sampling::sizeError(fit, truth);
}

void record(Errors& e, const sampling::SuperquadricFit& fit, double ms, const Superquadric& truth) {
  e.size_pct.push_back(sizeErrorPct(fit.shape, truth));
  e.center_mm.push_back(1000 * (fit.shape.pose.translation() - truth.pose.translation()).norm());
  e.eps.push_back(0.5 *
                  (std::abs(fit.shape.eps1 - truth.eps1) + std::abs(fit.shape.eps2 - truth.eps2)));
  e.ms.push_back(ms);
}

// The share of fits within the bounds: centre within 5 mm and
// every size within 10 %.
double withinBounds(const Errors& e) {
  int n = 0;
  for (std::size_t i = 0; i < e.size_pct.size(); ++i)
    n += e.size_pct[i] <= 10 && e.center_mm[i] <= 5;
  return e.size_pct.empty() ? 0.0 : double(n) / double(e.size_pct.size());
}

nlohmann::json toJson(const Errors& e) {
  return {{"within_5mm_10pct", withinBounds(e)},
          {"size_err_pct", distribution(e.size_pct)},
          {"center_err_mm", distribution(e.center_mm)},
          {"eps_err", distribution(e.eps)},
          {"ms_per_fit", distribution(e.ms)["median"]}};
}

// Where an operator would click: the rock's centroid, or the rock pixel
// nearest it that is not a feature.
std::optional<Eigen::Vector2d> operatorSeed(const std::vector<Eigen::Vector2d>& px,
                                            const sampling::FeatureMap& f) {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const auto& p : px) centre += p / double(px.size());
  std::optional<Eigen::Vector2d> best;
  for (const auto& p : px)
    if (!f.isFeature(int(p.y()), int(p.x())) &&
        (!best || (p - centre).norm() < (*best - centre).norm()))
      best = p;
  return best;
}

// Stray points: uniform in a box around the rock, from below its centre to
// twice its height above.
void addOutliers(std::vector<Eigen::Vector3d>& points, double share, const Superquadric& rock,
                 std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const double h = 1.5 * std::max(rock.size.x(), rock.size.y());
  const Eigen::Vector3d c = rock.pose.translation();
  std::uniform_real_distribution<double> x(c.x() - h, c.x() + h), y(c.y() - h, c.y() + h),
      z(c.z() - rock.size.z(), c.z() + 2 * rock.size.z());
  const auto n = std::size_t(std::lround(share / (1 - share) * double(points.size())));
  for (std::size_t i = 0; i < n; ++i) points.push_back({x(rng), y(rng), z(rng)});
}

void evaluateScene(std::uint64_t seed, std::pair<double, double> burial, double noise,
                   double outlier_share, Condition& out) {
  const sim::ProceduralTerrain terrain(
      sim::makeWorkArea({.seed = seed, .burial_min = burial.first, .burial_max = burial.second}));
  sim::StriperModel model;
  model.noise_sigma = noise;
  const auto scene = sim::simulateStriper(terrain, model, seed);
  const auto& image = scene.image;
  const auto features = sampling::extractFeatures(image);
  const auto seeds = sampling::automaticSeeds(image, features);
  std::map<int, std::vector<Eigen::Vector2d>> rocks;
  for (int r = 0; r < image.rows(); ++r)
    for (int c = 0; c < image.cols(); ++c)
      if (const int l = scene.labels(r, c); l != sim::kLabelGround && l != sim::kLabelNothing)
        rocks[l].push_back({double(c), double(r)});
  auto labelAt = [&](const Eigen::Vector2d& p) {
    return int(scene.labels(int(std::lround(p.y())), int(std::lround(p.x()))));
  };
  out.seeds += int(seeds.size());
  for (const auto& s : seeds) {
    const int l = labelAt(s.pixel);
    out.false_seeds += l == sim::kLabelGround || l == sim::kLabelNothing;
  }
  for (const auto& [label, px] : rocks) {
    if (px.size() < 80) continue;  // barely visible: nothing to sample
    const auto& truth =
        std::get<sim::Rock>(terrain.description().features[std::size_t(label - 1)]).shape;
    ++out.rocks;
    out.seeded += std::any_of(seeds.begin(), seeds.end(),
                              [&](const auto& s) { return labelAt(s.pixel) == label; });
    const auto click = operatorSeed(px, features);
    if (!click) continue;
    const auto contour = sampling::growContour(features, *click);
    const auto mask = sampling::contourMask(contour, image.rows(), image.cols());
    int both = 0, either = 0;
    for (std::size_t i = 0; i < mask.pixels.size(); ++i) {
      const bool a = mask.pixels[i] != 0, b = scene.labels.pixels[i] == label;
      both += a && b, either += a || b;
    }
    out.iou.push_back(double(both) / either);
    const auto rock = sampling::rockPoints(image, contour);
    const auto& points = rock.points;
    if (points.size() < 11) continue;
    std::vector<Eigen::Vector3d> stray = points;
    addOutliers(stray, outlier_share, truth, seed * 100 + std::uint64_t(label));
    // LM and robust on the radial distance; LM on Solina's residual, the
    // paper's, for comparison.
    const std::pair<const char*, sampling::FitOptions> methods[] = {
        {"lm", {.residual = sampling::FitResidual::kRadial, .robust = false}},
        {"robust", {.residual = sampling::FitResidual::kRadial, .robust = true}},
        {"lm_solina", {.residual = sampling::FitResidual::kSolina, .robust = false}}};
    for (const auto& [name, options] : methods) {
      auto& errors = out.methods[name];
      for (const bool with_outliers : {false, true}) {
        const auto& set = with_outliers ? stray : points;
        const auto start = std::chrono::steady_clock::now();
        const auto fit = sampling::fitSuperquadric(set, options, rock.sand);
        record(with_outliers ? errors.outliers : errors.clean, fit, millisecondsSince(start),
               truth);
      }
    }
  }
}

struct EvalRocksArgs {
  std::vector<std::uint64_t> seeds{1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  double noise = 0.0005;
  double outliers = 0.2;
  bool json = true;  // the only output form
};

nlohmann::json evalRocks(const EvalRocksArgs& args) {
  nlohmann::json report{
      {"scenes", args.seeds.size()}, {"noise_m", args.noise}, {"outlier_share", args.outliers}};
  // Isolated rocks resting on the sand (up to a fifth of their height in
  // it), and partly buried ones (half to three quarters in it: the widest
  // part hidden).
  const std::pair<const char*, std::pair<double, double>> conditions[] = {
      {"resting", {0.0, 0.2}}, {"partly_buried", {0.5, 0.75}}};
  for (const auto& [name, burial] : conditions) {
    Condition c;
    for (const auto seed : args.seeds) evaluateScene(seed, burial, args.noise, args.outliers, c);
    nlohmann::json condition{
        {"rocks", c.rocks},
        {"auto_seed_recall", c.rocks ? double(c.seeded) / c.rocks : 0.0},
        {"auto_seed_precision", c.seeds ? 1.0 - double(c.false_seeds) / c.seeds : 0.0},
        {"contour_iou", distribution(c.iou)}};
    std::sort(c.iou.begin(), c.iou.end());
    condition["contour_iou"]["min"] = c.iou.empty() ? 0.0 : c.iou.front();
    for (const auto& [method, e] : c.methods) {
      condition[method] = toJson(e.clean);
      condition[method]["with_outliers"] = toJson(e.outliers);
    }
    report[name] = condition;
  }
  return report;
}

struct FitRockArgs {
  std::string striper;
  std::string seed;
  bool automatic = false;
  bool robust = false;
  bool json = true;  // the only output form
};

nlohmann::json describe(const sampling::RockSample& s) {
  const auto& q = s.fit.shape;
  const Eigen::Vector3d c = q.pose.translation();
  const Eigen::Quaterniond rot(q.pose.linear());
  nlohmann::json grasp{{"ok", s.grasp.ok}};
  if (s.grasp.ok)
    grasp.update({{"x_m", s.grasp.centre.x()},
                  {"y_m", s.grasp.centre.y()},
                  {"z_m", s.grasp.centre.z()},
                  {"yaw_deg", s.grasp.yaw_rad * 180 / M_PI},
                  {"opening_m", s.grasp.opening_m}});
  else
    grasp["reason"] = s.grasp.reason;
  return {{"seed", {int(std::lround(s.seed.y())), int(std::lround(s.seed.x()))}},
          {"contour",
           {{"points", s.contour.points.size()},
            {"area_px", s.contour.areaPx()},
            {"iterations", s.contour.iterations},
            {"converged", s.contour.converged}}},
          {"points", s.points.size()},
          {"superquadric",
           {{"centre_m", {c.x(), c.y(), c.z()}},
            {"size_m", {q.size.x(), q.size.y(), q.size.z()}},
            {"eps1", q.eps1},
            {"eps2", q.eps2},
            {"rotation_wxyz", {rot.w(), rot.x(), rot.y(), rot.z()}},
            {"rms_m", s.fit.rms_m},
            {"inlier_share", s.fit.inlier_share},
            {"iterations", s.fit.iterations},
            {"converged", s.fit.converged},
            {"ms", s.fit_ms}}},
          {"grasp", grasp}};
}

void runFitRock(const FitRockArgs& args) {
  const auto image = sensor::readStriperImage(args.striper);
  const auto features = sampling::extractFeatures(image);
  sampling::SamplingOptions options;
  options.fit.robust = args.robust;
  std::vector<Eigen::Vector2d> seeds;
  if (args.automatic) {
    for (const auto& s : sampling::automaticSeeds(image, features, options.seeds))
      seeds.push_back(s.pixel);
  } else {
    const auto rc = parseNumbers(args.seed, 2, "--seed", "ROW,COL");
    if (rc[0] != std::round(rc[0]) || rc[1] != std::round(rc[1]))
      throw std::invalid_argument("--seed '" + args.seed + "': ROW and COL are whole pixels");
    seeds.push_back({rc[1], rc[0]});
  }
  nlohmann::json rocks = nlohmann::json::array();
  for (const auto& seed : seeds) {
    try {
      rocks.push_back(describe(sampling::sampleRock(image, features, seed, options)));
    } catch (const std::invalid_argument& e) {
      if (!args.automatic) throw;  // the operator's seed: say why it failed
      rocks.push_back({{"seed", {int(std::lround(seed.y())), int(std::lround(seed.x()))}},
                       {"error", e.what()}});
    }
  }
  printJson({{"striper", args.striper},
             {"method", args.robust ? "robust" : "lm"},
             {"features",
              {{"shadow_px", features.count(sampling::kShadow)},
               {"range_edge_px", features.count(sampling::kRangeEdge)},
               {"normal_edge_px", features.count(sampling::kNormalEdge)},
               {"regions", features.region_count}}},
             {"rocks", rocks}});
}

}  // namespace

void addEvalRocks(CLI::App& eval, Evaluations& all) {
  all.push_back({"rocks", [] { return evalRocks(EvalRocksArgs{}); }});
  auto args = std::make_shared<EvalRocksArgs>();
  auto* cmd = eval.add_subcommand(
      "rocks",
      "Rock sampling on simulated striper scenes: automatic seeds, contours, superquadric fits "
      "(LM and robust, clean and with outliers) against the simulator's rocks");
  cmd->add_option("--seeds", args->seeds, "scene seeds")->delimiter(',')->capture_default_str();
  cmd->add_option("--noise", args->noise, "striper noise along the camera ray [m]")
      ->check(CLI::Range(0.0, 0.01))
      ->capture_default_str();
  cmd->add_option("--outliers", args->outliers, "share of stray points added to each rock")
      ->check(CLI::Range(0.0, 0.9))
      ->capture_default_str();
  cmd->add_flag("--json", args->json, "print JSON (the only output form)");
  cmd->callback([args] { printJson(evalRocks(*args)); });
}

void addFitRock(CLI::App& app) {
  auto args = std::make_shared<FitRockArgs>();
  auto* cmd = app.add_subcommand(
      "fit-rock", "Contour, superquadric and grasp of the rock around a seed in a striper image");
  cmd->add_option("--striper", args->striper, "striper folder (docs/formats.md)")->required();
  auto* seed = cmd->add_option("--seed", args->seed, "a pixel inside the rock, ROW,COL");
  auto* automatic =
      cmd->add_flag("--auto", args->automatic, "every automatic seed (from range shadows)");
  seed->excludes(automatic);
  cmd->add_flag("--robust", args->robust, "robust fit (Cauchy weights)");
  cmd->add_flag("--json", args->json, "print JSON (the only output form)");
  cmd->callback([args, seed, automatic] {
    if (!*seed && !*automatic)
      throw std::invalid_argument("fit-rock needs --seed ROW,COL or --auto");
    runFitRock(*args);
  });
}

}  // namespace ambler::cli
