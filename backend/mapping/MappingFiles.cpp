#include "mapping/MappingFiles.h"

#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>
#include <vtkCellArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPLYReader.h>
#include <vtkPLYWriter.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <cmath>

#include "io/FormatError.h"
#include "io/Npz.h"
#include "io/PcdHeader.h"

namespace ambler::mapping {

namespace {

void requireFile(const std::filesystem::path& path, const char* kind) {
  if (!std::filesystem::is_regular_file(path))
    throw io::FormatError(std::string(kind) + " '" + path.string() + "': file does not exist");
}

}  // namespace

Cloud readCloud(const std::filesystem::path& pcd) {
  io::checkPcd(pcd, true);  // before PCL, which crashes on some malformed files
  pcl::PointCloud<pcl::PointXYZ> xyz;
  if (pcl::io::loadPCDFile(pcd.string(), xyz) < 0)
    throw io::FormatError("PCD '" + pcd.string() + "': malformed, truncated or without x, y, z");
  Cloud out;
  for (const auto& p : xyz)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
      out.push_back(p.getVector3fMap().cast<double>());
  return out;
}

void writeCloud(const std::filesystem::path& pcd, const Cloud& cloud) {
  pcl::PointCloud<pcl::PointXYZ> xyz;
  for (const auto& p : cloud) xyz.push_back({float(p.x()), float(p.y()), float(p.z())});
  if (xyz.empty() || pcl::io::savePCDFileBinary(pcd.string(), xyz) < 0)
    throw io::FormatError("PCD '" + pcd.string() + "': cannot write " +
                          std::to_string(cloud.size()) + " points there");
}

TerrainMesh readMesh(const std::filesystem::path& ply) {
  requireFile(ply, "PLY");
  vtkNew<vtkPLYReader> reader;
  reader->SetFileName(ply.string().c_str());
  reader->Update();
  vtkPolyData* data = reader->GetOutput();
  if (data == nullptr || data->GetNumberOfPoints() < 3 || data->GetNumberOfPolys() < 1)
    throw io::FormatError("PLY '" + ply.string() + "': malformed, truncated or without triangles");
  TerrainMesh mesh;
  for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i) {
    double p[3];
    data->GetPoint(i, p);
    mesh.vertices.push_back({p[0], p[1], p[2]});
    if (!mesh.vertices.back().allFinite())
      throw io::FormatError("PLY '" + ply.string() + "': vertex " + std::to_string(i) +
                            " is not finite");
  }
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < data->GetNumberOfCells(); ++c) {
    data->GetCellPoints(c, ids);
    if (ids->GetNumberOfIds() != 3)
      throw io::FormatError("PLY '" + ply.string() + "': face " + std::to_string(c) +
                            " is not a triangle");
    mesh.triangles.push_back({int(ids->GetId(0)), int(ids->GetId(1)), int(ids->GetId(2))});
  }
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
