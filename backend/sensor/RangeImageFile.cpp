#include "sensor/RangeImageFile.h"

#include "core/Angles.h"
#include "core/Pose.h"
#include "io/Json.h"
#include "io/Tiff.h"

namespace ambler::sensor {

namespace {

constexpr const char* kModel = "spherical_polar";

RangeImage parseSidecar(const io::JsonFields& f) {
  if (const auto model = f.string("model"); model != kModel)
    f.fail("model", "is \"" + model + "\"; only \"" + kModel + "\" is supported");
  RangeImage image;
  auto& g = image.geometry;
  g.rows = f.integer("rows");
  g.cols = f.integer("cols");
  if (g.rows <= 0 || g.cols <= 0) f.fail("rows", "and cols must be positive");
  g.phi_first = f.number("phi_first_deg") * kDeg;
  g.phi_step = f.number("phi_step_deg") * kDeg;
  g.theta_first = f.number("theta_first_deg") * kDeg;
  g.theta_step = f.number("theta_step_deg") * kDeg;
  image.range_sigma_k = f.number("range_sigma_k");
  image.sensor_to_world = poseFromRowMajor(f.numbers("sensor_to_world", 16));
  return image;
}

std::filesystem::path siblingPath(const std::filesystem::path& tiff_path, const std::string& name) {
  return tiff_path.parent_path() / name;
}

}  // namespace

std::filesystem::path sidecarPath(const std::filesystem::path& tiff_path) {
  auto p = tiff_path;
  return p.replace_extension(".json");
}

RangeImage readRangeImage(const std::filesystem::path& tiff_path) {
  const auto json_path = sidecarPath(tiff_path);
  const auto json = io::readJsonFile(json_path);
  const io::JsonFields fields(json, "range-image sidecar '" + json_path.string() + "'");
  RangeImage image = parseSidecar(fields);
  const io::FloatImage ranges = io::readFloatTiff(tiff_path);
  io::requireSize(ranges, image.rows(), image.cols(), tiff_path, "its sidecar");
  image.range = ranges.pixels;

  if (fields.has("reflectance_file")) {
    const auto refl_path = siblingPath(tiff_path, fields.string("reflectance_file"));
    const auto refl = io::readFloatTiff(refl_path);
    io::requireSize(refl, image.rows(), image.cols(), refl_path, "the range image's sidecar");
    image.reflectance = refl.pixels;
  }
  if (const auto problem = findProblem(image); !problem.empty())
    throw io::FormatError("range image '" + tiff_path.string() + "': " + problem);
  return image;
}

void writeRangeImage(const RangeImage& image, const std::filesystem::path& tiff_path) {
  if (const auto problem = findProblem(image); !problem.empty())
    throw io::FormatError("refusing to write range image '" + tiff_path.string() + "': " + problem);
  const auto& g = image.geometry;
  nlohmann::json json = {
      {"model", kModel},
      {"rows", g.rows},
      {"cols", g.cols},
      {"phi_first_deg", g.phi_first / kDeg},
      {"phi_step_deg", g.phi_step / kDeg},
      {"theta_first_deg", g.theta_first / kDeg},
      {"theta_step_deg", g.theta_step / kDeg},
      {"range_sigma_k", image.range_sigma_k},
      {"sensor_to_world", toRowMajor(image.sensor_to_world)},
  };
  io::FloatImage ranges;
  ranges.rows = g.rows;
  ranges.cols = g.cols;
  ranges.pixels = image.range;
  io::writeTiff(tiff_path, ranges);
  if (!image.reflectance.empty()) {
    const auto name = tiff_path.stem().string() + "_reflectance.tif";
    io::FloatImage refl = ranges;
    refl.pixels = image.reflectance;
    io::writeTiff(siblingPath(tiff_path, name), refl);
    json["reflectance_file"] = name;
  }
  // The sidecar goes last: a reader never sees a sidecar without its data.
  io::writeJsonFile(sidecarPath(tiff_path), json);
}

}  // namespace ambler::sensor
