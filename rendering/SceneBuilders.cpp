#include "rendering/SceneBuilders.h"

#include <fontconfig/fontconfig.h>
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkSphereSource.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "rendering/ColorMap.h"

namespace ambler::rendering {

vtkSmartPointer<vtkLookupTable> makeViridisTable(double lo, double hi) {
  auto table = vtkSmartPointer<vtkLookupTable>::New();
  table->SetNumberOfTableValues(256);
  table->SetRange(lo, hi > lo ? hi : lo + 1e-3);
  for (int i = 0; i < 256; ++i) {
    const auto c = viridis(i / 255.0);
    table->SetTableValue(i, c[0] / 255.0, c[1] / 255.0, c[2] / 255.0, 1.0);
  }
  table->SetNanColor(kNoDataColor[0] / 255.0, kNoDataColor[1] / 255.0, kNoDataColor[2] / 255.0,
                     1.0);
  table->Build();
  return table;
}

vtkSmartPointer<vtkActor> makeHeightSurface(const GridSpec& grid, const io::FloatImage& z,
                                            vtkLookupTable* table) {
  vtkNew<vtkPoints> points;
  points->SetNumberOfPoints(vtkIdType(grid.rows) * grid.cols);
  vtkNew<vtkFloatArray> heights;
  heights->SetName("elevation_m");
  heights->SetNumberOfValues(vtkIdType(grid.rows) * grid.cols);
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) {
      const auto xy = grid.cellCenter(r, c);
      const float h = z(r, c);
      const vtkIdType id = grid.index(r, c);
      points->SetPoint(id, xy.x(), xy.y(), std::isfinite(h) ? h : 0.0);
      heights->SetValue(id, h);
    }
  vtkNew<vtkCellArray> triangles;
  for (int r = 0; r + 1 < grid.rows; ++r)
    for (int c = 0; c + 1 < grid.cols; ++c) {
      const vtkIdType a = grid.index(r, c), b = a + 1, d = grid.index(r + 1, c), e = d + 1;
      if (!(std::isfinite(z(r, c)) && std::isfinite(z(r, c + 1)) && std::isfinite(z(r + 1, c)) &&
            std::isfinite(z(r + 1, c + 1))))
        continue;
      const vtkIdType t1[3] = {a, b, e}, t2[3] = {a, e, d};
      triangles->InsertNextCell(3, t1);
      triangles->InsertNextCell(3, t2);
    }
  vtkNew<vtkPolyData> surface;
  surface->SetPoints(points);
  surface->SetPolys(triangles);
  surface->GetPointData()->SetScalars(heights);

  vtkNew<vtkPolyDataNormals> normals;  // smooth shading shows the relief
  normals->SetInputData(surface);
  normals->SplittingOff();
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(normals->GetOutputPort());
  mapper->SetLookupTable(table);
  mapper->UseLookupTableScalarRangeOn();
  mapper->SetScalarModeToUsePointData();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  return actor;
}

std::pair<GridSpec, io::FloatImage> thinned(const GridSpec& grid, const io::FloatImage& z,
                                            int max_cells) {
  const int k =
      std::max(1, int(std::ceil(std::sqrt(double(grid.cellCount()) / std::max(max_cells, 1)))));
  GridSpec out = grid;
  out.resolution = grid.resolution * k;
  out.origin_x = grid.origin_x + 0.5 * grid.resolution - 0.5 * out.resolution;
  out.origin_y = grid.origin_y + 0.5 * grid.resolution - 0.5 * out.resolution;
  out.rows = (grid.rows + k - 1) / k, out.cols = (grid.cols + k - 1) / k;
  io::FloatImage thin(out.rows, out.cols);
  for (int r = 0; r < out.rows; ++r)
    for (int c = 0; c < out.cols; ++c) thin(r, c) = z(r * k, c * k);
  return {out, std::move(thin)};
}

vtkSmartPointer<vtkActor> makePointCloud(const std::vector<Eigen::Vector3f>& pts,
                                         const Eigen::Vector3d& rgb, float point_size) {
  vtkNew<vtkPoints> points;
  points->SetNumberOfPoints(vtkIdType(pts.size()));
  vtkNew<vtkCellArray> vertices;
  for (vtkIdType i = 0; i < vtkIdType(pts.size()); ++i) {
    points->SetPoint(i, pts[std::size_t(i)].x(), pts[std::size_t(i)].y(), pts[std::size_t(i)].z());
    vertices->InsertNextCell(1, &i);
  }
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(points);
  cloud->SetVerts(vertices);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(cloud);
  mapper->ScalarVisibilityOff();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(rgb.x(), rgb.y(), rgb.z());
  actor->GetProperty()->SetPointSize(point_size);
  actor->GetProperty()->LightingOff();
  return actor;
}

namespace {

// The file of the desktop's sans-serif font as fontconfig matches it, the
// font Qt draws the rest of the GUI in; empty when there is none. VTK's
// built-in Arial draws '[' as '(': the bars' units read "(m)" beside the
// Qt bars' "[m]".
const std::string& sansFontFile() {
  static const std::string file = [] {
    std::string out;
    FcPattern* pattern = FcNameParse(reinterpret_cast<const FcChar8*>("sans-serif"));
    if (!pattern) return out;
    FcConfigSubstitute(nullptr, pattern, FcMatchPattern);
    FcDefaultSubstitute(pattern);
    FcResult result = FcResultNoMatch;
    if (FcPattern* match = FcFontMatch(nullptr, pattern, &result)) {
      FcChar8* path = nullptr;
      if (FcPatternGetString(match, FC_FILE, 0, &path) == FcResultMatch)
        out = reinterpret_cast<const char*>(path);
      FcPatternDestroy(match);
    }
    FcPatternDestroy(pattern);
    return out;
  }();
  return file;
}

void useSansFont(vtkTextProperty* text) {
  if (sansFontFile().empty()) return;
  text->SetFontFamily(VTK_FONT_FILE);
  text->SetFontFile(sansFontFile().c_str());
}

}  // namespace

vtkSmartPointer<vtkScalarBarActor> makeColorBar(vtkLookupTable* table, const std::string& title,
                                                double pixel_ratio) {
  auto bar = vtkSmartPointer<vtkScalarBarActor>::New();
  bar->SetLookupTable(table);
  bar->SetTitle(title.c_str());
  double range[2];
  table->GetTableRange(range);
  const auto ticks = colorBarTicks(range[0], range[1]);
  vtkNew<vtkDoubleArray> labels;
  for (const double value : ticks.values) labels->InsertNextValue(value);
  bar->SetCustomLabels(labels);
  bar->UseCustomLabelsOn();
  bar->SetLabelFormat(("%." + std::to_string(ticks.decimals) + "f").c_str());
  bar->SetMaximumWidthInPixels(int(90 * pixel_ratio));
  // Far enough from the right edge that the centred title is not clipped
  // in narrow views.
  bar->SetPosition(kColorBarLeft, 0.1);
  bar->SetPosition2(0.17, 0.8);
  bar->GetTitleTextProperty()->SetFontSize(int(14 * pixel_ratio));
  bar->GetTitleTextProperty()->ItalicOff();
  bar->GetLabelTextProperty()->SetFontSize(int(12 * pixel_ratio));
  bar->GetLabelTextProperty()->ItalicOff();
  useSansFont(bar->GetTitleTextProperty());
  useSansFont(bar->GetLabelTextProperty());
  bar->UnconstrainedFontSizeOn();
  return bar;
}

vtkSmartPointer<vtkActor> makePolylines(const std::vector<std::vector<Eigen::Vector3d>>& strips,
                                        const Eigen::Vector3d& rgb, float width) {
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> lines;
  for (const auto& strip : strips) {
    if (strip.size() < 2) continue;
    lines->InsertNextCell(vtkIdType(strip.size()));
    for (const auto& p : strip) lines->InsertCellPoint(points->InsertNextPoint(p.data()));
  }
  vtkNew<vtkPolyData> data;
  data->SetPoints(points);
  data->SetLines(lines);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(data);
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(rgb.x(), rgb.y(), rgb.z());
  actor->GetProperty()->SetLineWidth(width);
  actor->GetProperty()->LightingOff();
  return actor;
}

vtkSmartPointer<vtkActor> makeSphere(const Eigen::Vector3d& centre, double radius,
                                     const Eigen::Vector3d& rgb) {
  vtkNew<vtkSphereSource> sphere;
  sphere->SetCenter(centre.data());
  sphere->SetRadius(radius);
  sphere->SetThetaResolution(16);
  sphere->SetPhiResolution(12);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(sphere->GetOutputPort());
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(rgb.x(), rgb.y(), rgb.z());
  return actor;
}

}  // namespace ambler::rendering
