#pragma once

#include <vtkActor.h>
#include <vtkLookupTable.h>
#include <vtkScalarBarActor.h>
#include <vtkSmartPointer.h>

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "core/GridSpec.h"
#include "io/Image.h"

namespace ambler::rendering {

// Viridis lookup table over [lo, hi]; NaN shows in the no-data colour.
vtkSmartPointer<vtkLookupTable> makeViridisTable(double lo, double hi);

// A shaded surface through the grid's cell centres at height z [m],
// coloured by z through `table`. Quads touching a NaN height are left out.
vtkSmartPointer<vtkActor> makeHeightSurface(const GridSpec& grid, const io::FloatImage& z,
                                            vtkLookupTable* table);

// The grid thinned to at most `max_cells` cells by keeping every k-th row
// and column, their centres where they were: a stand-in for the surface
// while the camera moves.
std::pair<GridSpec, io::FloatImage> thinned(const GridSpec& grid, const io::FloatImage& z,
                                            int max_cells);

// Points drawn as screen-space dots of one colour (RGB in [0, 1]).
vtkSmartPointer<vtkActor> makePointCloud(const std::vector<Eigen::Vector3f>& points,
                                         const Eigen::Vector3d& rgb, float point_size = 2.0f);

// Connected line strips of one colour, `width` pixels wide (the rover's
// legs, a support polygon, a path).
vtkSmartPointer<vtkActor> makePolylines(const std::vector<std::vector<Eigen::Vector3d>>& strips,
                                        const Eigen::Vector3d& rgb, float width = 3.0f);

// A shaded sphere (a foothold, a foot).
vtkSmartPointer<vtkActor> makeSphere(const Eigen::Vector3d& centre, double radius,
                                     const Eigen::Vector3d& rgb);

// Where makeColorBar()'s bar begins, as a share of the view's width from
// its left edge: a scene drawn right of it runs under the bar.
inline constexpr double kColorBarLeft = 0.80;

// A vertical colour bar for `table` whose title carries the unit, e.g.
// "Elevation [m]" (a "\n" breaks a long one); `pixel_ratio` is the
// screen's device pixels per logical pixel, so the bar keeps its size on
// a high-density screen.
vtkSmartPointer<vtkScalarBarActor> makeColorBar(vtkLookupTable* table, const std::string& title,
                                                double pixel_ratio = 1.0);

}  // namespace ambler::rendering
