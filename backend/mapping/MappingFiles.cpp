#include "mapping/MappingFiles.h"

#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>
#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPLYWriter.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <cmath>

#include "io/FormatError.h"
#include "io/Npz.h"
#include "io/Pcd.h"
#include "io/Ply.h"

namespace ambler::mapping {

Cloud readCloud(const std::filesystem::path& pcd) { return readScan(pcd).points; }

ScanFile readScan(const std::filesystem::path& pcd) {
  const auto cloud = io::readPcd(pcd, true);
  const int x = cloud.header.column("x"), y = cloud.header.column("y"),
            z = cloud.header.column("z");
  Cloud out;
  out.reserve(cloud.header.points);
  const std::size_t per_point = cloud.header.elementsPerPoint();
  for (std::uint64_t i = 0; i < cloud.header.points; ++i) {
    const double* values = &cloud.values[i * per_point];
    const Eigen::Vector3d p(values[x], values[y], values[z]);
    if (p.allFinite()) out.push_back(p);
  }
  ScanFile scan{std::move(out), std::nullopt};
  if (const auto& v = cloud.header.viewpoint)
    scan.scanner = Eigen::Vector3d((*v)[0], (*v)[1], (*v)[2]);
  return scan;
}

void writeCloud(const std::filesystem::path& pcd, const Cloud& cloud,
                const Eigen::Vector3d& scanner) {
  pcl::PointCloud<pcl::PointXYZ> xyz;
  xyz.sensor_origin_ =
      Eigen::Vector4f(float(scanner.x()), float(scanner.y()), float(scanner.z()), 0.0f);
  for (const auto& p : cloud) xyz.push_back({float(p.x()), float(p.y()), float(p.z())});
  if (xyz.empty() || pcl::io::savePCDFileBinary(pcd.string(), xyz) < 0)
    throw io::FormatError("PCD '" + pcd.string() + "': cannot write " +
                          std::to_string(cloud.size()) + " points there");
}

TerrainMesh readMesh(const std::filesystem::path& ply) {
  const auto file = io::readPly(ply);
  if (file.vertices.size() < 3 || file.triangles.empty())
    throw io::FormatError(ply.string() + ": PLY has fewer than 3 vertices or no triangle");
  TerrainMesh mesh;
  for (const auto& v : file.vertices) mesh.vertices.emplace_back(v[0], v[1], v[2]);
  for (const auto& t : file.triangles) mesh.triangles.push_back({int(t[0]), int(t[1]), int(t[2])});
  connect(mesh);
  return mesh;
}

void writeMesh(const std::filesystem::path& ply, const TerrainMesh& mesh) {
  vtkNew<vtkPoints> points;
  for (const auto& v : mesh.vertices) points->InsertNextPoint(v.x(), v.y(), v.z());
  vtkNew<vtkCellArray> faces;
  for (const auto& t : mesh.triangles) {
    const vtkIdType ids[3] = {t[0], t[1], t[2]};
    faces->InsertNextCell(3, ids);
  }
  vtkNew<vtkPolyData> data;
  data->SetPoints(points);
  data->SetPolys(faces);
  vtkNew<vtkPLYWriter> writer;
  writer->SetFileName(ply.string().c_str());
  writer->SetInputData(data);
  writer->SetFileTypeToBinary();
  if (writer->Write() != 1)
    throw io::FormatError("PLY '" + ply.string() + "': cannot write the mesh there");
}

Cloud readDem(const std::filesystem::path& npz) {
  const auto arrays = io::readNpz(npz);
  auto array = [&](const std::string& key) -> const io::NpyArray& {
    const auto it = arrays.find(key);
    if (it == arrays.end())
      throw io::FormatError("DEM '" + npz.string() + "': no array '" + key + "'");
    return it->second;
  };
  auto scalar = [&](const std::string& key) {
    const auto& a = array(key);
    if (a.values.size() != 1 || !std::isfinite(a.values[0]))
      throw io::FormatError("DEM '" + npz.string() + "': '" + key + "' is not one finite number");
    return a.values[0];
  };
  const auto& elevation = array("elevation");
  if (elevation.shape.size() != 2 || elevation.shape[0] < 2 || elevation.shape[1] < 2)
    throw io::FormatError("DEM '" + npz.string() + "': 'elevation' is not a grid of 2 x 2 or more");
  const auto rows = elevation.shape[0], cols = elevation.shape[1];
  const double lon0 = scalar("xmin"), lon1 = scalar("xmax");
  const double lat0 = scalar("ymin"), lat1 = scalar("ymax");
  if (std::abs(lat0) > 89 || std::abs(lat1) > 89)
    throw io::FormatError("DEM '" + npz.string() + "': latitudes beyond 89 degrees");
  constexpr double kMetresPerDegree = 6371000.0 * M_PI / 180;  // mean Earth radius
  const double east = kMetresPerDegree * std::cos(0.5 * (lat0 + lat1) * M_PI / 180);
  Cloud cloud;
  cloud.reserve(rows * cols);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c) {
      const double z = elevation.values[r * cols + c];
      if (!std::isfinite(z)) continue;
      const double u = (double(c) + 0.5) / double(cols) - 0.5;
      const double v = (double(r) + 0.5) / double(rows) - 0.5;
      cloud.emplace_back(u * (lon1 - lon0) * east, v * (lat1 - lat0) * kMetresPerDegree, z);
    }
  return cloud;
}

}  // namespace ambler::mapping
