// The irregular triangulated mesh and paths over it (bakambu-csa §3-4) on
// analytic terrains.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include <filesystem>

#include "io/FormatError.h"
#include "mapping/MappingFiles.h"
#include "mapping/TerrainMesh.h"
#include "mapping/TerrainPath.h"

namespace ambler::mapping {
namespace {

using Height = std::function<double(double, double)>;

// Points every `step` over [x0, x1] x [y0, y1] on the surface z = h(x, y).
std::vector<Eigen::Vector3d> sampled(const Height& h, double x0, double y0, double x1, double y1,
                                     double step = 0.1) {
  std::vector<Eigen::Vector3d> out;
  for (double y = y0; y <= y1 + 1e-9; y += step)
    for (double x = x0; x <= x1 + 1e-9; x += step) out.push_back({x, y, h(x, y)});
  return out;
}

// The mesh's height under xy.
double heightOn(const TerrainMesh& m, const TriangleLocator& at, const Eigen::Vector2d& xy) {
  return m.pointOn(at.at(xy).value(), xy).z();
}

TEST(TerrainMesh, APlaneIsAFewLargeTrianglesOnIt) {
  const Height plane = [](double x, double y) { return 0.1 * x + 0.05 * y + 1.0; };
  const auto mesh = triangulate(sampled(plane, 0, 0, 10, 10));
  EXPECT_LE(mesh.size(), 64u);
  const double slope = std::atan(std::hypot(0.1, 0.05));
  for (const auto& v : mesh.vertices) EXPECT_NEAR(v.z(), plane(v.x(), v.y()), 1e-9);
  double area = 0;
  for (int t = 0; t < int(mesh.size()); ++t) {
    EXPECT_NEAR(mesh.slopeRad(t), slope, 1e-9);
    area += mesh.areaXY(t);
  }
  EXPECT_NEAR(area, 100.0, 1.0);  // the whole square, nothing beyond it
}

TEST(TerrainMesh, RoughGroundGetsSmallTrianglesAndStaysWithinTolerance) {
  // Flat, with a bump 1 m high in one corner.
  const Height bumpy = [](double x, double y) {
    return std::exp(-(std::pow(x - 7.5, 2) + std::pow(y - 7.5, 2)) / 0.8);
  };
  const MeshOptions options{.tolerance_m = 0.02, .min_cell_m = 0.1};
  const auto mesh = triangulate(sampled(bumpy, 0, 0, 10, 10), options);
  double rough_area = 0, flat_area = 0;
  int rough = 0, flat = 0;
  for (int t = 0; t < int(mesh.size()); ++t) {
    const Eigen::Vector3d c = mesh.centre(t);
    if ((c.head<2>() - Eigen::Vector2d(7.5, 7.5)).norm() < 1.0)
      rough_area += mesh.areaXY(t), ++rough;
    if (c.x() < 4 && c.y() < 4) flat_area += mesh.areaXY(t), ++flat;
  }
  ASSERT_GT(rough, 0);
  ASSERT_GT(flat, 0);
  EXPECT_LT(rough_area / rough, 0.05 * flat_area / flat) << rough << " vs " << flat;
  // Within the tolerance on the plane's part; near the bump the mesh
  // follows the cells' means (errors of the order of the cell's curvature).
  const TriangleLocator at(mesh);
  for (const auto& p : sampled(bumpy, 0.05, 0.05, 9.95, 9.95, 0.3))
    EXPECT_NEAR(heightOn(mesh, at, p.head<2>()), p.z(), 0.06) << p.transpose();
  for (const auto& p : sampled(bumpy, 0.05, 0.05, 4, 4, 0.3))
    EXPECT_NEAR(heightOn(mesh, at, p.head<2>()), p.z(), options.tolerance_m) << p.transpose();
}

TEST(TerrainMesh, GapsInTheDataStayGaps) {
  auto points = sampled([](double, double) { return 0.0; }, 0, 0, 10, 3);
  const auto far = sampled([](double, double) { return 0.0; }, 0, 7, 10, 10);
  points.insert(points.end(), far.begin(), far.end());
  const auto mesh = triangulate(points);
  const TriangleLocator at(mesh);
  EXPECT_TRUE(at.at({5.0, 1.5}).has_value());
  EXPECT_FALSE(at.at({5.0, 5.0}).has_value());
  for (int t = 0; t < int(mesh.size()); ++t)
    for (int k = 0; k < 3; ++k) {
      const int n = mesh.neighbours[std::size_t(t)][std::size_t(k)];
      if (n < 0) continue;
      EXPECT_NE(std::find(mesh.neighbours[std::size_t(n)].begin(),
                          mesh.neighbours[std::size_t(n)].end(), t),
                mesh.neighbours[std::size_t(n)].end());
    }
}

TEST(TerrainMesh, BadInputIsRefusedWithTheProblemNamed) {
  EXPECT_THROW(triangulate({{0, 0, 0}, {1, 0, NAN}, {0, 1, 0}}), std::invalid_argument);
  MeshOptions bad;
  bad.tolerance_m = 0;
  EXPECT_THROW(triangulate(sampled([](double, double) { return 0.0; }, 0, 0, 1, 1), bad),
               std::invalid_argument);
}

// A cone 3 m high and 4 m across (56 degree flanks) between start and goal.
double cone(double x, double y) { return std::max(0.0, 3.0 - 1.5 * std::hypot(x - 10, y - 5)); }

TEST(TerrainPath, GoesAroundTooSteepGroundAndSimplifies) {
  const auto mesh = triangulate(sampled(cone, 0, 0, 20, 10));
  const PathOptions options;  // slope cost, 20 degree limit
  const auto path = planPath(mesh, {2, 5}, {18, 5}, options);
  ASSERT_TRUE(path.found) << path.reason;
  const double limit = options.max_slope_deg * M_PI / 180;
  for (int t : path.triangles) EXPECT_LE(mesh.slopeRad(t), limit);
  // The simplified path, sampled every centimetre, stays on safe triangles.
  const TriangleLocator at(mesh);
  for (std::size_t k = 1; k < path.simplified.size(); ++k)
    for (double u = 0; u <= 1; u += 0.001) {
      const Eigen::Vector2d xy = path.simplified[k - 1].head<2>() +
                                 u * (path.simplified[k] - path.simplified[k - 1]).head<2>();
      const auto t = at.at(xy);
      ASSERT_TRUE(t.has_value()) << xy.transpose();
      EXPECT_LE(mesh.slopeRad(*t), limit + 1e-9) << xy.transpose();
    }
  EXPECT_LT(path.simplified.size(), path.raw.size());
  EXPECT_LE(path.simplified_cost, 1.05 * path.raw_cost);
  EXPECT_NEAR(polylineCost(mesh, at, path.simplified, options), path.simplified_cost,
              1e-9 * path.simplified_cost);
  EXPECT_GT(path.length_m, 16.0);  // the straight line crosses the cone
  EXPECT_LT(path.length_m, 16.0 * 1.25);
}

TEST(TerrainPath, OnFlatGroundTheShortestIsTheStraightLine) {
  const auto mesh = triangulate(sampled([](double, double) { return 0.0; }, 0, 0, 20, 10));
  PathOptions options;
  options.cost = PathCost::kDistance;
  const auto path = planPath(mesh, {1, 1}, {19, 9}, options);
  ASSERT_TRUE(path.found) << path.reason;
  EXPECT_EQ(path.simplified.size(), 2u);
  EXPECT_NEAR(path.length_m, std::hypot(18.0, 8.0), 1e-9);
}

TEST(TerrainPath, HighGroundIsFavouredWhenAsked) {
  // A plateau 0.5 m high on the north side, up a 14 degree ramp.
  const Height plateau = [](double, double y) { return std::clamp((y - 6.0) * 0.25, 0.0, 0.5); };
  const auto mesh = triangulate(sampled(plateau, 0, 0, 20, 16));
  PathOptions low, high;
  low.cost = PathCost::kSlope;
  high.cost = PathCost::kHighGround;
  high.low_ground_weight = 3.0;
  const auto a = planPath(mesh, {1, 4}, {19, 4}, low), b = planPath(mesh, {1, 4}, {19, 4}, high);
  ASSERT_TRUE(a.found && b.found);
  auto meanZ = [](const TerrainPath& p) {
    double z = 0;
    for (const auto& w : p.raw) z += w.z() / double(p.raw.size());
    return z;
  };
  EXPECT_LT(meanZ(a), 0.05);
  EXPECT_GT(meanZ(b), 0.3);
}

TEST(TerrainPath, SaysWhyThereIsNoPath) {
  const auto mesh = triangulate(sampled(cone, 0, 0, 20, 10));
  EXPECT_EQ(planPath(mesh, {-5, 5}, {18, 5}).reason, "the start is not on the mesh");
  EXPECT_EQ(planPath(mesh, {2, 5}, {10, 5.3}).reason,
            "the goal is on a triangle steeper than the slope limit");
  PathOptions bad;
  bad.max_slope_deg = 95;
  EXPECT_THROW(planPath(mesh, {2, 5}, {18, 5}, bad), std::invalid_argument);
}

TEST(MappingFiles, MeshesAndCloudsSurviveTheirFiles) {
  const auto dir = std::filesystem::temp_directory_path() / "ambler_mapping_files_test";
  std::filesystem::create_directories(dir);
  const auto points = sampled(cone, 0, 0, 20, 10, 0.5);
  writeCloud(dir / "cloud.pcd", points, Eigen::Vector3d(1.5, -2.0, 5.0));
  const auto cloud = readCloud(dir / "cloud.pcd");
  const auto scan = readScan(dir / "cloud.pcd");
  ASSERT_TRUE(scan.scanner.has_value());  // from the PCD's VIEWPOINT
  EXPECT_LT((*scan.scanner - Eigen::Vector3d(1.5, -2.0, 5.0)).norm(), 1e-6);
  ASSERT_EQ(cloud.size(), points.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) EXPECT_LT((cloud[i] - points[i]).norm(), 1e-5);
  const auto mesh = triangulate(cloud);
  writeMesh(dir / "mesh.ply", mesh);
  const auto back = readMesh(dir / "mesh.ply");
  EXPECT_EQ(back.triangles, mesh.triangles);
  EXPECT_EQ(back.neighbours, mesh.neighbours);
  ASSERT_EQ(back.vertices.size(), mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    EXPECT_LT((back.vertices[i] - mesh.vertices[i]).norm(), 1e-5);
  // A truncated PLY and a missing PCD are named.
  std::filesystem::resize_file(dir / "mesh.ply", 40);
  EXPECT_THROW(readMesh(dir / "mesh.ply"), io::FormatError);
  try {
    readCloud(dir / "missing.pcd");
    ADD_FAILURE();
  } catch (const io::FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.pcd"), std::string::npos);
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ambler::mapping

namespace ambler::mapping {
namespace {

// USGS's 3 arc-second DEM of the Jacksboro fault (Debian's
// python-matplotlib-data): 344 x 403 heights of 236-1076 m, the north-west
// corner 483 m, the south-east 272 m; 3 arc-seconds are 92.6 m north and
// 74.4 m east at 36.6 degrees north.
TEST(MappingFiles, ReadsTheJacksboroDemInMetresAroundItsCentre) {
  const auto dem = readDem("/usr/share/matplotlib/mpl-data/sample_data/jacksboro_fault_dem.npz");
  ASSERT_EQ(dem.size(), 344u * 403u);
  double low = INFINITY, high = -INFINITY;
  for (const auto& p : dem) low = std::min(low, p.z()), high = std::max(high, p.z());
  EXPECT_EQ(low, 236);
  EXPECT_EQ(high, 1076);
  const auto& north_west = dem.front();
  const auto& south_east = dem.back();
  EXPECT_EQ(north_west.z(), 483);
  EXPECT_EQ(south_east.z(), 272);
  EXPECT_NEAR(north_west.x(), -south_east.x(), 1e-6);
  EXPECT_NEAR(north_west.y(), -south_east.y(), 1e-6);
  EXPECT_NEAR((dem[1] - dem[0]).x(), 74.4, 0.3);    // one column east
  EXPECT_NEAR((dem[0] - dem[403]).y(), 92.6, 0.3);  // one row south
  EXPECT_GT(north_west.y(), 0);
  EXPECT_LT(north_west.x(), 0);
  EXPECT_THROW(readDem("/nonexistent/dem.npz"), io::FormatError);
}

}  // namespace
}  // namespace ambler::mapping
