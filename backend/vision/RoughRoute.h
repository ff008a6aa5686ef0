#pragma once

#include <string>
#include <vector>

#include "io/Image.h"
#include "vision/DangerMap.h"

namespace ambler::vision {

// A pixel position, column x from the left and row y from the bottom (the
// paper's figure 3).
struct ImagePoint {
  double x = 0.0, y = 0.0;
};

// ejiri §4.1: a rough route on the image from the Start Area (bottom
// centre, the rover's heading) to the Destination Area, as straight legs
// turning at Way Areas.
struct RouteOptions {
  // Dangerous: D above the mean D of the ground plus this share of the
  // gap to 1 (the paper ties the threshold to the image's mean shade).
  double threshold_share = 0.5;
  int max_way_areas = 8;
};

struct RoughRoute {
  bool found = false;
  std::string reason;             // why not, when not found
  double threshold = 0.0;         // D above which a pixel is dangerous
  ImagePoint start, destination;  // moved out of danger if they were in it
  bool start_moved = false, destination_moved = false;
  std::vector<ImagePoint> way_areas;  // WA_1, WA_2, ... in route order
  std::vector<ImagePoint> route;      // start, way areas, destination
};

// `danger` from degreeOfDanger() of an image from `camera`; `goal` the
// destination's pixel (default: the image's centre column, 3 rows below
// the horizon). Each leg is a corridor as wide as the shade window of its
// row (the rover's diagonal on the ground); a blocked leg turns, left or
// right, at the side that leaves the straight route less (then the less
// dangerous), just clear of the first obstacle.
RoughRoute planRoughRoute(const io::FloatImage& danger, const CameraModel& camera,
                          const ImagePoint* goal = nullptr, const RouteOptions& options = {});

// ejiri §4.2: the five-level Safe Rate and the sensing action along the
// route, per stretch in each distance band.
enum class SafeRate { kSafe, kALittleSafe, kALittleAttention, kAttention, kSpecialAttention };
enum class SensingAction { kA, kB, kC, kD, kE, kF };
const char* toString(SafeRate rate);
const char* describe(SensingAction action);  // "A: move without sensing", ...

struct SensingStep {
  std::string band;  // "start", "short", "middle", "long"
  ImagePoint from, to;
  SafeRate rate = SafeRate::kSafe;
  SensingAction action = SensingAction::kA;
};

// The plan: F at the start point; on each stretch of the route in the
// short and middle bands, a rate from the nearest dangerous pixel to the
// route (in corridor widths) and its action; E where the route reaches
// the long-distance band (docs/vision.md gives the table).
std::vector<SensingStep> planSensing(const io::FloatImage& danger, const CameraModel& camera,
                                     const RoughRoute& route);

}  // namespace ambler::vision
