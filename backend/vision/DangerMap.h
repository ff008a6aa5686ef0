#pragma once

#include <vector>

#include "io/Image.h"

namespace ambler::vision {

// ejiri §3.2: the payload camera over flat ground and the rover's sizes
// that set the windows.
struct CameraModel {
  int rows = 480;                 // Y, image height [pixel]
  double alpha_deg = 60.0;        // optical axis from the vertical (nadir) [deg]
  double beta_deg = 40.0;         // vertical field of view [deg]
  double height_m = 1.5;          // H, camera above the ground [m]
  double wheel_diameter_m = 0.3;  // T: the variance windows span T on the ground
  double rover_diagonal_m = 1.5;  // R: the shade windows span R on the ground
};

// Throws std::invalid_argument naming the first value out of range.
void validate(const CameraModel& camera);

// Image rows counted from the bottom (y = 0 nearest the rover), as in the
// paper's figure 3.
//
// Eq. 1: the angle, above the lower edge of the view, of the ground point
// (k + 1) d / 2 beyond where that edge meets the ground.
double windowAngle(const CameraModel& camera, int k, double d);
// The row (from the bottom, fractional) at which a ray `theta` above the
// lower edge of the view appears (the bracket of eq. 2).
double rowAt(const CameraModel& camera, double theta);
// Eq. 2: window k's width [pixel]; it spans the ground from (k - 1) d / 2
// to (k + 1) d / 2 (k >= 2), from 0 to (k + 1) d / 2 (k = 0, 1), so that
// neighbouring windows overlap by half.
double windowWidth(const CameraModel& camera, int k, double d);

// The bands of §3.2 and §4.2 [rows from the bottom]: below y_v the
// variance is computed too (windows of T wider than 2 pixels); below y_g
// the shade windows of R are wider than 2 pixels, above it 3-pixel windows
// up to the horizon y_h (the image top if the horizon is out of view).
struct Bands {
  int y_v = 0, y_g = 0, y_h = 0;
};
Bands bandsOf(const CameraModel& camera);

struct DangerOptions {
  double variance_threshold = 200.0;  // B [grey level^2]
  double max_brightness = 255.0;      // N
};

// Eqs. 3-4 on a grey-level image (row 0 at the top, as stored): for every
// window of its band (widths from eq. 2, overlapping by half across and
// along), the shade mean and, below y_v, the variance; each pixel averages
// those of the windows covering it into G and V, and
//   D = 1 - f0(V, B) G / N,   f0 = 1 where V <= B or at y >= y_v, else B / V.
// D is in [0, 1], larger where the rover goes less easily; NaN above the
// horizon. Throws std::invalid_argument if the image's height is not the
// camera's.
io::FloatImage degreeOfDanger(const io::FloatImage& image, const CameraModel& camera,
                              const DangerOptions& options = {});

}  // namespace ambler::vision
