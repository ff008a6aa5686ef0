#include "sensor/StriperImageFile.h"

#include "core/Pose.h"
#include "io/Json.h"
#include "io/Tiff.h"

namespace ambler::sensor {

namespace {

constexpr const char* kModel = "light_striper";
constexpr const char* kHeader = "striper.json";

struct Plane {
  const char* file;
  std::vector<float> StriperImage::*member;
};
constexpr Plane kPlanes[] = {{"x.tif", &StriperImage::x},
                             {"y.tif", &StriperImage::y},
                             {"z.tif", &StriperImage::z},
                             {"intensity.tif", &StriperImage::intensity}};

}  // namespace

bool isStriperFolder(const std::filesystem::path& folder) {
  return std::filesystem::is_regular_file(folder / kHeader);
}

StriperImage readStriperImage(const std::filesystem::path& folder) {
  const auto header_path = folder / kHeader;
  const auto json = io::readJsonFile(header_path);
  const io::JsonFields f(json, "striper header '" + header_path.string() + "'");
  if (const auto model = f.string("model"); model != kModel)
    f.fail("model", "is \"" + model + "\"; expected \"" + kModel + "\"");
  StriperImage image;
  auto& cam = image.camera;
  cam.rows = f.integer("rows");
  cam.cols = f.integer("cols");
  const auto c = f.object("camera");
  cam.fx = c.number("fx");
  cam.fy = c.number("fy");
  cam.cx = c.number("cx");
  cam.cy = c.number("cy");
  cam.camera_to_world = poseFromRowMajor(c.numbers("camera_to_world", 16));
  const auto proj = f.numbers("projector_position", 3);
  image.projector_position = {proj[0], proj[1], proj[2]};

  for (const auto& plane : kPlanes) {
    const auto data = io::readFloatTiff(folder / plane.file);
    io::requireSize(data, cam.rows, cam.cols, folder / plane.file, "the header");
    image.*plane.member = data.pixels;
  }
  if (const auto problem = findProblem(image); !problem.empty())
    throw io::FormatError("striper image '" + folder.string() + "': " + problem);
  return image;
}

void writeStriperImage(const StriperImage& image, const std::filesystem::path& folder) {
  if (const auto problem = findProblem(image); !problem.empty())
    throw io::FormatError("refusing to write striper image '" + folder.string() + "': " + problem);
  std::filesystem::create_directories(folder);
  for (const auto& plane : kPlanes) {
    io::FloatImage data;
    data.rows = image.rows();
    data.cols = image.cols();
    data.pixels = image.*plane.member;
    io::writeTiff(folder / plane.file, data);
  }
  const auto& cam = image.camera;
  const auto& p = image.projector_position;
  io::writeJsonFile(folder / kHeader, {{"model", kModel},
                                       {"rows", cam.rows},
                                       {"cols", cam.cols},
                                       {"camera",
                                        {{"fx", cam.fx},
                                         {"fy", cam.fy},
                                         {"cx", cam.cx},
                                         {"cy", cam.cy},
                                         {"camera_to_world", toRowMajor(cam.camera_to_world)}}},
                                       {"projector_position", {p.x(), p.y(), p.z()}}});
}

}  // namespace ambler::sensor
