// ambler-cli danger: the degree of danger of one grey-level camera image
// (ejiri §3) as a float32 TIFF, and the rough route and sensing plan on it
// (§4) as JSON.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

#include "cli/Arguments.h"
#include "cli/Commands.h"
#include "core/Resources.h"
#include "io/Json.h"
#include "io/Tiff.h"
#include "sim/CameraRender.h"
#include "sim/CourseScene.h"
#include "vision/RoughRoute.h"
#include "vision/VisionFiles.h"

namespace ambler::cli {

namespace {

struct DangerArgs {
  std::string image, camera, out, goal;
  double threshold = 0.5;
  bool json = true;  // the only output form
};

// Image points in the files as (column, row from the top), like the image.
nlohmann::json pixel(const vision::ImagePoint& p, int rows) { return {p.x, rows - 1 - p.y}; }

nlohmann::json routeJson(const vision::RoughRoute& r, int rows) {
  nlohmann::json way = nlohmann::json::array(), route = nlohmann::json::array();
  for (const auto& p : r.way_areas) way.push_back(pixel(p, rows));
  for (const auto& p : r.route) route.push_back(pixel(p, rows));
  return {{"found", r.found},
          {"reason", r.reason},
          {"threshold", r.threshold},
          {"start", pixel(r.start, rows)},
          {"start_moved", r.start_moved},
          {"destination", pixel(r.destination, rows)},
          {"destination_moved", r.destination_moved},
          {"way_areas", way},
          {"route", route}};
}

nlohmann::json sensingJson(const std::vector<vision::SensingStep>& plan, int rows) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& s : plan)
    out.push_back({{"band", s.band},
                   {"from", pixel(s.from, rows)},
                   {"to", pixel(s.to, rows)},
                   {"safe_rate", vision::toString(s.rate)},
                   {"action", vision::describe(s.action)}});
  return out;
}

void runDanger(const DangerArgs& args) {
  const auto camera =
      vision::readCameraFile(args.camera.empty() ? findResource("config/camera.json")
                                                 : std::filesystem::path(args.camera));
  const auto image = vision::readGreyImage(args.image);
  const auto start = std::chrono::steady_clock::now();
  const auto danger = vision::degreeOfDanger(image, camera.camera, camera.danger);
  std::optional<vision::ImagePoint> goal;
  if (!args.goal.empty()) {
    const auto g = parseNumbers(args.goal, 2, "--goal", "COLUMN,ROW");
    goal = vision::ImagePoint{g[0], image.rows - 1 - g[1]};
  }
  const auto route = vision::planRoughRoute(danger, camera.camera, goal ? &*goal : nullptr);
  const auto sensing = vision::planSensing(danger, camera.camera, route);
  const double ms = millisecondsSince(start);
  const auto bands = vision::bandsOf(camera.camera);
  std::size_t ground = 0, dangerous = 0;
  for (const float d : danger.pixels)
    if (std::isfinite(d)) ++ground, dangerous += d > args.threshold;
  const std::filesystem::path dir(args.out);
  std::filesystem::create_directories(dir);
  io::writeTiff(dir / "danger.tif", danger);
  const nlohmann::json summary{
      {"image", args.image},
      {"rows", image.rows},
      {"cols", image.cols},
      {"bands_rows_from_bottom", {{"y_v", bands.y_v}, {"y_g", bands.y_g}, {"y_h", bands.y_h}}},
      {"threshold", args.threshold},
      {"dangerous_fraction", ground ? double(dangerous) / double(ground) : 0.0},
      {"danger", (dir / "danger.tif").string()},
      {"route", routeJson(route, image.rows)},
      {"sensing", sensingJson(sensing, image.rows)},
      {"ms", ms}};
  io::writeJsonFile(dir / "danger.json", summary);
  printJson(summary);
}

// The course seen by the camera of `camera` from the rover at `xy` facing
// `heading` [rad], shaded by the simulator, with its rough-pixel truth.
sim::RenderedImage shadedCourse(const sim::CourseScene& scene, const vision::CameraModel& camera,
                                const Eigen::Vector2d& xy, double heading,
                                std::uint64_t texture_seed) {
  sim::CameraShot shot;
  shot.rows = camera.rows, shot.alpha_deg = camera.alpha_deg, shot.beta_deg = camera.beta_deg;
  shot.height_m = camera.height_m, shot.ground_xy = xy, shot.heading = heading;
  shot.texture_seed = texture_seed;
  // A course scene: its terrain is procedural.
  return sim::renderCamera(dynamic_cast<const sim::ProceduralTerrain&>(scene.terrain()),
                           scene.caster(), shot, 0.5 * camera.wheel_diameter_m);
}

struct EvalDangerArgs {
  std::vector<std::uint64_t> seeds{1, 2, 3, 4, 5};
  std::vector<double> headings_deg{0, 90, 180, 270};
  bool json = true;  // the only output form
};

// Images the simulator shades (no planetary images are packaged): D
// against the pixels that see a feature standing off the ground, and the
// route against them.
nlohmann::json evalDanger(const EvalDangerArgs& args) {
  const auto camera = vision::readCameraFile(findResource("config/camera.json"));
  std::vector<double> recall, precision, on_rough, ms;
  int routes = 0, cases = 0;
  for (const auto seed : args.seeds) {
    const sim::CourseScene scene(seed, sim::readScannerModel(findResource("config/scanner.json")));
    for (const double heading : args.headings_deg) {
      const auto render =
          shadedCourse(scene, camera.camera, Eigen::Vector2d::Zero(), heading * M_PI / 180, seed);
      const auto start = std::chrono::steady_clock::now();
      const auto danger = vision::degreeOfDanger(render.grey, camera.camera, camera.danger);
      const auto route = vision::planRoughRoute(danger, camera.camera);
      ms.push_back(millisecondsSince(start));
      ++cases;
      std::size_t rough = 0, found = 0, flagged = 0;
      for (std::size_t i = 0; i < danger.pixels.size(); ++i) {
        if (!std::isfinite(danger.pixels[i]) || render.rough.pixels[i] == 255) continue;
        const bool dangerous = danger.pixels[i] > route.threshold;
        rough += render.rough.pixels[i] == 1;
        found += dangerous && render.rough.pixels[i] == 1;
        flagged += dangerous;
      }
      if (rough > 0) recall.push_back(double(found) / double(rough));
      if (flagged > 0) precision.push_back(double(found) / double(flagged));
      if (!route.found) continue;
      ++routes;
      std::size_t points = 0, bad = 0;
      for (std::size_t leg = 0; leg + 1 < route.route.size(); ++leg)
        for (double t = 0; t <= 1.0; t += 0.002, ++points) {
          const auto& a = route.route[leg];
          const auto& b = route.route[leg + 1];
          const int col = int(std::lround(a.x + t * (b.x - a.x)));
          const int row = danger.rows - 1 - int(std::lround(a.y + t * (b.y - a.y)));
          bad += render.rough(row, col) == 1;
        }
      on_rough.push_back(points ? double(bad) / double(points) : 0.0);
    }
  }
  return {{"cases", cases},
          {"rough_rule", "the pixel sees a feature more than half a wheel off the ground"},
          {"recall", distribution(recall)},
          {"precision", distribution(precision)},
          {"routes_found", routes},
          {"route_share_on_rough", distribution(on_rough)},
          {"ms", distribution(ms)}};
}

}  // namespace

void addSimCamera(CLI::App& app) {
  struct Args {
    std::uint64_t seed = 1;
    std::string at = "0,0,0", out;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "sim-camera",
      "Shade a grey-level payload-camera image of the obstacle course (config/camera.json)");
  cmd->add_option("--seed", args->seed, "course seed")->capture_default_str();
  cmd->add_option("--at", args->at, "rover position X,Y [m] and heading [deg, 0: +y]")
      ->capture_default_str();
  cmd->add_option("--out", args->out, "output folder")->required();
  cmd->callback([args] {
    const auto at = parseRoverAt(args->at);
    const auto camera = vision::readCameraFile(findResource("config/camera.json")).camera;
    const double heading = at.heading_deg * M_PI / 180;
    // Placed where the camera stands, so that a start off the course is refused.
    const sim::CourseScene scene(
        args->seed, sim::readScannerModel(findResource("config/scanner.json")), at.xy, heading);
    const auto render = shadedCourse(scene, camera, at.xy, heading, args->seed);
    io::ByteImage grey(render.grey.rows, render.grey.cols);
    for (std::size_t i = 0; i < grey.pixels.size(); ++i)
      grey.pixels[i] = static_cast<unsigned char>(std::lround(render.grey.pixels[i]));
    const std::filesystem::path dir(args->out);
    std::filesystem::create_directories(dir);
    io::writeTiff(dir / "image.tif", grey);
    io::writeTiff(dir / "rough.tif", render.rough);
    printJson(
        {{"image", (dir / "image.tif").string()},
         {"rough", (dir / "rough.tif").string()},
         {"rows", grey.rows},
         {"cols", grey.cols},
         {"rough_codes",
          {{"0", "ground"}, {"1", "rough: a feature > T/2 off the ground"}, {"255", "sky"}}}});
  });
}

void addEvalDanger(CLI::App& eval, Evaluations& all) {
  all.push_back({"danger", [] { return evalDanger(EvalDangerArgs{}); }});
  auto args = std::make_shared<EvalDangerArgs>();
  auto* cmd = eval.add_subcommand(
      "danger", "Degree of danger and rough route on camera images the simulator shades");
  cmd->add_option("--seeds", args->seeds, "course seeds")->delimiter(',')->capture_default_str();
  cmd->add_option("--headings", args->headings_deg, "camera headings [deg]")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_flag("--json", args->json, "print JSON (the only output form)");
  cmd->callback([args] { printJson(evalDanger(*args)); });
}

void addDanger(CLI::App& app) {
  auto args = std::make_shared<DangerArgs>();
  auto* cmd = app.add_subcommand(
      "danger", "Degree of danger D(x, y) of a grey-level camera image (float32 TIFF, NaN sky)");
  cmd->add_option("image", args->image, "grey-level image (PNG, PGM, JPEG, TIFF)")->required();
  cmd->add_option("--camera", args->camera, "camera model JSON (default: config/camera.json)");
  cmd->add_option("--out", args->out, "output folder")->required();
  cmd->add_option("--goal", args->goal,
                  "destination pixel COLUMN,ROW (row from the top; default: the centre column "
                  "just below the horizon)");
  cmd->add_option("--threshold", args->threshold,
                  "D above which a pixel counts in dangerous_fraction")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_flag("--json", args->json, "print JSON (the only output form)");
  cmd->callback([args] { runDanger(*args); });
}

}  // namespace ambler::cli
