// SPDX-License-Identifier: MIT
// Plate images from a run's series files: front and rear orthographic views per plate, and the
// page layout, colour maps and particle glyphs the other report images share.
#include "render/plate_images.hpp"

#include "core/common/error.hpp"
#include "core/common/toml_check.hpp"
#include "render/osmesa_context.hpp"
#include "render/series_writer.hpp"
#include "render/vtk_errors.hpp"

#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCoordinate.h>
#include <vtkDataSetSurfaceFilter.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkGlyph3DMapper.h>
#include <vtkIdList.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkProperty.h>
#include <vtkProperty2D.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSphereSource.h>
#include <vtkStringArray.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkVariant.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fesph {

namespace fs = std::filesystem;

namespace render_detail {

namespace {

// Nearest entry of a .pvd (time < 0: the last one); empty when the .pvd is missing or empty.
std::string nearestFile(const fs::path& pvd, double time, double* found_time) {
  if (!fs::exists(pvd)) return {};
  const PvdCollection series(pvd, /*append=*/true);  // append: read only, never deletes
  const auto& entries = series.entries();
  if (entries.empty()) return {};
  std::size_t best = entries.size() - 1;
  if (time >= 0)
    for (std::size_t k = 0; k < entries.size(); ++k)
      if (std::abs(entries[k].time - time) < std::abs(entries[best].time - time)) best = k;
  if (found_time) *found_time = entries[best].time;
  return (pvd.parent_path() / entries[best].file).string();
}

vtkSmartPointer<vtkTextActor> text(const std::string& s, int size, bool bold) {
  auto t = vtkSmartPointer<vtkTextActor>::New();
  t->SetInput(s.c_str());
  vtkTextProperty* p = t->GetTextProperty();
  p->SetFontFamilyToArial();
  p->SetFontSize(size);
  p->SetBold(bold);
  p->SetColor(0.1, 0.1, 0.1);
  return t;
}

}  // namespace

RunStep readRunStep(const std::string& run_dir, double time) {
  RunStep step;
  const std::string vtu = nearestFile(fs::path(run_dir) / "elements.pvd", time, &step.time);
  if (vtu.empty()) throw RunError(run_dir + ": no element series (elements.pvd)");
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(vtu.c_str());
  clearVtkError();
  reader->Update();
  if (reader->GetErrorCode() != 0 || !vtkError().empty())  // a file cut short sets no code
    throw RunError(cannotRead(vtu, reader->GetErrorCode()));
  step.elements = reader->GetOutput();

  // Particles of the same output step: the .vtp nearest to the element step's time.
  step.particles = readParticles(run_dir, step.time);
  return step;
}

vtkSmartPointer<vtkPolyData> readParticles(const std::string& run_dir, double time) {
  const std::string vtp = nearestFile(fs::path(run_dir) / "particles.pvd", time, nullptr);
  if (vtp.empty()) return nullptr;
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(vtp.c_str());
  clearVtkError();
  reader->Update();
  if (reader->GetErrorCode() != 0 || !vtkError().empty())
    throw RunError(cannotRead(vtp, reader->GetErrorCode()));
  return reader->GetOutput();
}

std::string timeLabel(double time) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "t = %.1f \u00b5s", time * 1e6);
  return buf;
}

std::string fieldTitle(const std::string& field, double* scale) {
  *scale = 1.0;
  if (field == "damage") return "Damage";
  if (field == "plastic_strain") return "Plastic strain";
  if (field == "plastic_strain_rate") return "Plastic strain rate (1/s)";
  if (field == "temperature") return "Temperature (K)";
  if (field == "density") return "Density (kg/m\u00b3)";
  if (field == "material") return "Material";
  if (field == "pressure" || field == "von_mises") {
    *scale = 1e-6;
    return field == "pressure" ? "Pressure (MPa)" : "von Mises stress (MPa)";
  }
  return field;
}

vtkSmartPointer<vtkPolyDataMapper> fieldMapper(vtkPolyData* skin, vtkLookupTable* lut) {
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  mapper->SetInputData(skin);
  mapper->SetScalarModeToUseCellFieldData();
  mapper->SelectColorArray("shown");
  mapper->SetLookupTable(lut);
  mapper->UseLookupTableScalarRangeOn();
  mapper->ScalarVisibilityOn();
  return mapper;
}

Page makePage(vtkRenderWindow* window, int width, int height) {
  Page page;
  page.width = width;
  page.height = height;
  page.overlay = vtkSmartPointer<vtkRenderer>::New();
  page.overlay->SetBackground(1, 1, 1);
  page.scene = vtkSmartPointer<vtkRenderer>::New();
  page.scene->SetBackground(1, 1, 1);
  page.scene->SetViewport(kSceneViewport[0], kSceneViewport[1], kSceneViewport[2],
                          kSceneViewport[3]);
  window->AddRenderer(page.overlay);
  window->AddRenderer(page.scene);
  return page;
}

void addTitle(Page& page, const std::string& title, const std::string& subtitle) {
  auto t = text(title, std::max(12, page.height / 34), true);
  t->GetTextProperty()->SetJustificationToCentered();
  t->GetTextProperty()->SetVerticalJustificationToTop();
  t->SetPosition(0.5 * page.width, page.height - 0.012 * page.height);
  page.overlay->AddActor2D(t);
  if (subtitle.empty()) return;
  auto s = text(subtitle, std::max(10, page.height / 52), false);
  s->GetTextProperty()->SetJustificationToCentered();
  s->GetTextProperty()->SetVerticalJustificationToTop();
  s->SetPosition(0.5 * page.width, page.height - 0.055 * page.height);
  page.overlay->AddActor2D(s);
}

void addScaleBar(Page& page, double pixel_size) {
  const double scene_width = (kSceneViewport[2] - kSceneViewport[0]) * page.width * pixel_size;
  const double target = 0.2 * scene_width;
  const double decade = std::pow(10.0, std::floor(std::log10(target)));
  double length = decade;
  for (double f : {2.0, 5.0})
    if (f * decade <= target) length = f * decade;
  const double px = length / pixel_size;

  const double x0 = 0.04 * page.width, y0 = 0.035 * page.height, tick = 0.012 * page.height;
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(x0, y0, 0);
  pts->InsertNextPoint(x0 + px, y0, 0);
  pts->InsertNextPoint(x0, y0 - tick, 0);
  pts->InsertNextPoint(x0, y0 + tick, 0);
  pts->InsertNextPoint(x0 + px, y0 - tick, 0);
  pts->InsertNextPoint(x0 + px, y0 + tick, 0);
  vtkNew<vtkCellArray> lines;
  for (vtkIdType a : {0, 2, 4}) {
    const vtkIdType ids[2] = {a, a + 1};
    lines->InsertNextCell(2, ids);
  }
  vtkNew<vtkPolyData> bar;
  bar->SetPoints(pts);
  bar->SetLines(lines);
  vtkNew<vtkCoordinate> display;
  display->SetCoordinateSystemToDisplay();
  vtkNew<vtkPolyDataMapper2D> mapper;
  mapper->SetInputData(bar);
  mapper->SetTransformCoordinate(display);
  vtkNew<vtkActor2D> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.1, 0.1, 0.1);
  actor->GetProperty()->SetLineWidth(std::max(2.0, page.height / 400.0));
  page.overlay->AddActor2D(actor);

  char buf[32];
  std::snprintf(buf, sizeof buf, "%g mm", length * 1e3);
  auto label = text(buf, std::max(10, page.height / 52), false);
  label->GetTextProperty()->SetVerticalJustificationToCentered();
  label->SetPosition(x0 + px + 0.012 * page.width, y0);
  page.overlay->AddActor2D(label);
}

int niceRange(double& lo, double& hi) {
  if (!(hi > lo)) hi = lo + (lo == 0 ? 1.0 : 0.1 * std::abs(lo));
  const double raw = (hi - lo) / 5;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10 * decade;
  for (double f : {1.0, 2.0, 2.5, 5.0})
    if (f * decade >= raw * 0.999) {
      step = f * decade;
      break;
    }
  lo = std::floor(lo / step + 1e-9) * step;
  hi = std::ceil(hi / step - 1e-9) * step;
  return static_cast<int>(std::lround((hi - lo) / step)) + 1;
}

// Categories (a lookup table of named values, fieldColours' for "material"): a swatch and its
// name for each, where the scalar bar goes. VTK's scalar bar squeezes such names to a few
// pixels beside its swatches.
void addLegend(Page& page, vtkLookupTable* lut, const std::string& title) {
  const double x0 = (kSceneViewport[2] + 0.015) * page.width, top = 0.86 * page.height;
  const double swatch = page.height / 30.0, gap = 0.5 * swatch;
  auto heading = text(title, std::max(10, page.height / 50), true);
  heading->SetPosition(x0, top);
  page.overlay->AddActor2D(heading);
  // Names as large as the scalar bar's labels, smaller where the longest would run off the
  // page (a character is about 0.6 of the font size wide).
  std::size_t longest = 1;
  for (vtkIdType k = 0; k < lut->GetNumberOfAnnotatedValues(); ++k)
    longest = std::max(longest, lut->GetAnnotation(k).size());
  const double room = 0.99 * page.width - (x0 + 1.4 * swatch);
  const int font = std::max(
      7, std::min(page.height / 60, static_cast<int>(room / (0.6 * static_cast<double>(longest)))));
  for (vtkIdType k = 0; k < lut->GetNumberOfAnnotatedValues(); ++k) {
    const double y = top - (k + 1) * (swatch + gap);
    vtkNew<vtkPoints> pts;
    pts->InsertNextPoint(x0, y, 0);
    pts->InsertNextPoint(x0 + swatch, y, 0);
    pts->InsertNextPoint(x0 + swatch, y + swatch, 0);
    pts->InsertNextPoint(x0, y + swatch, 0);
    vtkNew<vtkCellArray> quad;
    const vtkIdType ids[4] = {0, 1, 2, 3};
    quad->InsertNextCell(4, ids);
    vtkNew<vtkPolyData> square;
    square->SetPoints(pts);
    square->SetPolys(quad);
    vtkNew<vtkCoordinate> display;
    display->SetCoordinateSystemToDisplay();
    vtkNew<vtkPolyDataMapper2D> mapper;
    mapper->SetInputData(square);
    mapper->SetTransformCoordinate(display);
    vtkNew<vtkActor2D> actor;
    actor->SetMapper(mapper);
    double rgba[4];
    lut->GetIndexedColor(k, rgba);
    actor->GetProperty()->SetColor(rgba[0], rgba[1], rgba[2]);
    page.overlay->AddActor2D(actor);
    auto name = text(lut->GetAnnotation(k), font, false);
    name->GetTextProperty()->SetVerticalJustificationToCentered();
    name->SetPosition(x0 + 1.4 * swatch, y + 0.5 * swatch);
    page.overlay->AddActor2D(name);
  }
}

void addScalarBar(Page& page, vtkScalarsToColors* lut, const std::string& title, int labels) {
  if (auto* table = vtkLookupTable::SafeDownCast(lut); table && table->GetIndexedLookup())
    return addLegend(page, table, title);
  vtkNew<vtkScalarBarActor> bar;
  bar->SetLookupTable(lut);
  bar->SetTitle(title.c_str());
  bar->SetNumberOfLabels(labels);
  // As many decimals as the label step needs (0.25 -> 2, 0.2 -> 1, 50 -> 0).
  const double* range = lut->GetRange();
  const double step = (range[1] - range[0]) / std::max(1, labels - 1);
  int decimals = 0;
  while (decimals < 6 && std::abs(step * std::pow(10.0, decimals) -
                                   std::round(step * std::pow(10.0, decimals))) > 1e-6)
    ++decimals;
  const bool huge = std::max(std::abs(range[0]), std::abs(range[1])) >= 1e6;
  const std::string format = huge ? "%.3g" : "%." + std::to_string(decimals) + "f";
  bar->SetLabelFormat(format.c_str());
  bar->UnconstrainedFontSizeOn();
  bar->SetBarRatio(0.25);
  bar->SetVerticalTitleSeparation(std::max(4, page.height / 60));
  bar->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  bar->GetPositionCoordinate()->SetValue(kSceneViewport[2] + 0.015, 0.14);
  bar->SetWidth(0.97 - kSceneViewport[2]);
  bar->SetHeight(0.72);
  for (vtkTextProperty* p : {bar->GetTitleTextProperty(), bar->GetLabelTextProperty()}) {
    p->SetFontFamilyToArial();
    p->SetColor(0.1, 0.1, 0.1);
    p->ShadowOff();
    p->ItalicOff();
  }
  bar->GetTitleTextProperty()->SetFontSize(std::max(10, page.height / 50));
  bar->GetTitleTextProperty()->BoldOn();
  bar->GetLabelTextProperty()->SetFontSize(std::max(9, page.height / 60));
  bar->GetLabelTextProperty()->BoldOff();
  page.overlay->AddActor2D(bar);
}

vtkSmartPointer<vtkLookupTable> viridis(double lo, double hi) {
  // Viridis at nine evenly spaced points (matplotlib), interpolated linearly to 256 colours.
  static const double cp[9][3] = {{0.267, 0.005, 0.329}, {0.279, 0.175, 0.483},
                                  {0.230, 0.322, 0.546}, {0.173, 0.449, 0.558},
                                  {0.128, 0.567, 0.551}, {0.153, 0.683, 0.502},
                                  {0.369, 0.789, 0.383}, {0.678, 0.864, 0.190},
                                  {0.993, 0.906, 0.144}};
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  lut->SetNumberOfTableValues(256);
  for (int k = 0; k < 256; ++k) {
    const double s = 8.0 * k / 255.0;
    const int i = std::min(7, static_cast<int>(s));
    const double f = s - i;
    lut->SetTableValue(k, cp[i][0] + f * (cp[i + 1][0] - cp[i][0]),
                       cp[i][1] + f * (cp[i + 1][1] - cp[i][1]),
                       cp[i][2] + f * (cp[i + 1][2] - cp[i][2]), 1.0);
  }
  lut->SetTableRange(lo, hi);
  return lut;
}

vtkSmartPointer<vtkLookupTable> fieldColours(const std::string& field, double lo, double hi,
                                             vtkDataObject* data) {
  auto* names = field == "material" && data
                    ? vtkStringArray::SafeDownCast(
                          data->GetFieldData()->GetAbstractArray("material_names"))
                    : nullptr;
  if (!names || names->GetNumberOfValues() == 0) return viridis(lo, hi);
  // One colour per material, spread over viridis, each named in the legend (addScalarBar).
  const vtkIdType n = names->GetNumberOfValues();
  const vtkSmartPointer<vtkLookupTable> spread = viridis(0, std::max<vtkIdType>(1, n - 1));
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  lut->SetNumberOfTableValues(n);
  for (vtkIdType k = 0; k < n; ++k) {
    double rgb[3];
    spread->GetColor(static_cast<double>(k), rgb);
    lut->SetTableValue(k, rgb[0], rgb[1], rgb[2], 1.0);
  }
  lut->SetTableRange(0, std::max<vtkIdType>(1, n - 1));
  lut->IndexedLookupOn();
  for (vtkIdType k = 0; k < n; ++k)
    lut->SetAnnotation(vtkVariant(static_cast<double>(k)), names->GetValue(k));
  return lut;
}

void bodyColour(int b, double rgb[3]) {
  // Warm and neutral colours that viridis (purple-blue-green-yellow) does not use.
  static const double palette[6][3] = {{0.84, 0.15, 0.16}, {1.00, 0.50, 0.05},
                                       {0.55, 0.34, 0.29}, {0.89, 0.47, 0.76},
                                       {0.50, 0.50, 0.50}, {0.09, 0.75, 0.81}};
  const int k = ((b % 6) + 6) % 6;
  for (int c = 0; c < 3; ++c) rgb[c] = palette[k][c];
}

std::vector<vtkIdType> particlesOf(vtkPolyData* particles, int body) {
  std::vector<vtkIdType> ids;
  vtkDataArray* bodies = particles ? particles->GetPointData()->GetArray("body") : nullptr;
  for (vtkIdType i = 0; bodies && i < particles->GetNumberOfPoints(); ++i)
    if (static_cast<int>(bodies->GetTuple1(i)) == body) ids.push_back(i);
  return ids;
}

std::vector<DebrisParticle> plateParticles(vtkPolyData* particles,
                                           const std::vector<vtkIdType>& ids) {
  vtkDataArray* radius = particles->GetPointData()->GetArray("radius");
  vtkDataArray* mass = particles->GetPointData()->GetArray("mass");
  vtkDataArray* damage = particles->GetPointData()->GetArray("damage");
  if (!radius || !mass || !damage)
    throw RunError("particle series without \"radius\", \"mass\" and \"damage\" arrays");
  std::vector<DebrisParticle> list;
  for (vtkIdType i : ids) {
    DebrisParticle q;
    particles->GetPoint(i, q.x.data());
    q.radius = radius->GetTuple1(i);
    q.mass = mass->GetTuple1(i);
    q.damage = damage->GetTuple1(i);
    q.body = 0;  // one plate's
    list.push_back(q);
  }
  return list;
}

vtkSmartPointer<vtkActor> particleActor(vtkPolyData* particles, const std::vector<vtkIdType>& keep,
                                        vtkScalarsToColors* lut, const std::string& field,
                                        double unit, bool mirror_y) {
  if (!particles || keep.empty()) return nullptr;
  vtkDataArray* radius = particles->GetPointData()->GetArray("radius");
  vtkDataArray* body = particles->GetPointData()->GetArray("body");
  vtkDataArray* value = lut ? particles->GetPointData()->GetArray(field.c_str()) : nullptr;
  if (!value) lut = nullptr;  // a field the particles lack: their body's colour, not a 0
  if (!radius) throw RunError("particle series without a \"radius\" array");

  vtkNew<vtkPoints> pts;
  vtkNew<vtkDoubleArray> r;
  r->SetName("radius");
  vtkNew<vtkUnsignedCharArray> rgb;
  rgb->SetName("colour");
  rgb->SetNumberOfComponents(3);
  vtkNew<vtkDoubleArray> v;
  v->SetName("value");
  // Mirror images are mirrored points, not a mirrored actor: a negative scale would turn the
  // spheres' normals inwards and shade them black.
  for (int copy = 0; copy < (mirror_y ? 2 : 1); ++copy) {
    for (vtkIdType i : keep) {
      double x[3];
      particles->GetPoint(i, x);
      if (copy == 1) x[1] = -x[1];
      pts->InsertNextPoint(x);
      r->InsertNextValue(radius->GetTuple1(i));
      if (lut) {
        v->InsertNextValue(value->GetTuple1(i) * unit);
      } else {
        double c[3];
        bodyColour(body ? static_cast<int>(body->GetTuple1(i)) : 0, c);
        rgb->InsertNextTuple3(255 * c[0], 255 * c[1], 255 * c[2]);
      }
    }
  }
  vtkNew<vtkPolyData> subset;
  subset->SetPoints(pts);
  subset->GetPointData()->AddArray(r);
  subset->GetPointData()->AddArray(lut ? static_cast<vtkDataArray*>(v) : rgb);

  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(1.0);  // scaled by each particle's radius
  sphere->SetThetaResolution(14);
  sphere->SetPhiResolution(10);
  vtkNew<vtkGlyph3DMapper> mapper;
  mapper->SetInputData(subset);
  mapper->SetSourceConnection(sphere->GetOutputPort());
  mapper->SetScaleArray("radius");
  mapper->SetScaleModeToScaleByMagnitude();
  mapper->ScalingOn();
  mapper->SetScalarModeToUsePointFieldData();
  if (lut) {
    mapper->SelectColorArray("value");
    mapper->SetLookupTable(lut);
    mapper->UseLookupTableScalarRangeOn();
  } else {
    mapper->SelectColorArray("colour");
    mapper->SetColorModeToDirectScalars();
  }
  mapper->ScalarVisibilityOn();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetAmbient(0.25);
  actor->GetProperty()->SetDiffuse(0.8);
  return actor;
}

}  // namespace render_detail

using namespace render_detail;

RunInfo readRunInfo(const std::string& run_dir) {
  RunInfo info;
  std::ifstream history(fs::path(run_dir) / "history.csv");
  std::string header;
  if (history && std::getline(history, header)) {
    std::stringstream cols(header);
    std::string col;
    const std::string suffix = "_vx";
    while (std::getline(cols, col, ','))
      if (col.size() > suffix.size() && col.compare(col.size() - 3, 3, suffix) == 0)
        info.bodies.push_back({col.substr(0, col.size() - 3), false});
  }
  const fs::path scene = fs::path(run_dir) / "scene.toml";
  if (!fs::exists(scene)) return info;
  try {
    const toml::table root = tomlcheck::parseFile(scene.string());
    info.half = root["simulation"]["symmetry"].value_or(std::string()) == "half";
    if (const toml::array* bodies = root["bodies"].as_array()) {
      if (info.bodies.empty()) info.bodies.resize(bodies->size());
      for (std::size_t b = 0; b < bodies->size() && b < info.bodies.size(); ++b) {
        const toml::table* body = (*bodies)[b].as_table();
        if (!body) continue;
        if (info.bodies[b].name.empty())
          info.bodies[b].name = (*body)["name"].value_or(std::string());
        info.bodies[b].projectile = (*body)["projectile"].value_or(false);
      }
    }
  } catch (const InputError&) {
    // A scene that no longer parses still leaves the names from history.csv.
  }
  return info;
}

namespace {

// Cells of `grid` whose "body" value is `body`, with their cell data.
vtkSmartPointer<vtkUnstructuredGrid> extractBody(vtkUnstructuredGrid* grid, int body) {
  auto out = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkDataArray* bodies = grid->GetCellData()->GetArray("body");
  if (!bodies) throw RunError("element series without a \"body\" array");
  out->SetPoints(grid->GetPoints());
  out->GetPointData()->ShallowCopy(grid->GetPointData());
  vtkCellData* in_cd = grid->GetCellData();
  vtkCellData* out_cd = out->GetCellData();
  out_cd->CopyAllocate(in_cd);
  out->Allocate(grid->GetNumberOfCells());
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    if (static_cast<int>(bodies->GetTuple1(c)) != body) continue;
    grid->GetCellPoints(c, ids);
    const vtkIdType nc = out->InsertNextCell(grid->GetCellType(c), ids);
    out_cd->CopyData(in_cd, c, nc);
  }
  return out;
}

PlateHoles holesOf(vtkUnstructuredGrid* plate, const std::string& name, bool half) {
  std::vector<Vec3> x(static_cast<std::size_t>(plate->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < plate->GetNumberOfPoints(); ++i) plate->GetPoint(i, x[i].data());
  std::vector<std::array<int, 4>> tets;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < plate->GetNumberOfCells(); ++c) {
    plate->GetCellPoints(c, ids);
    if (ids->GetNumberOfIds() != 4) continue;
    tets.push_back({static_cast<int>(ids->GetId(0)), static_cast<int>(ids->GetId(1)),
                    static_cast<int>(ids->GetId(2)), static_cast<int>(ids->GetId(3))});
  }
  HoleOptions options;
  options.mirror = half;
  PlateHoles holes = findHoles(x, tets, options);
  holes.plate = name;
  return holes;
}

// A plate as drawn: its elements, or for a plate made of particles, its particles.
struct PlateView {
  int body;
  std::string name;
  vtkSmartPointer<vtkUnstructuredGrid> cells;
  std::vector<vtkIdType> particles;  ///< a plate made of particles (no cells): its particles
  PlateHoles holes;  ///< also the plate's frame and extent
};

std::string holeSummary(const PlateHoles& h) {
  if (h.holes.empty()) return "no through-hole";
  std::string s = std::to_string(h.holes.size()) +
                  (h.holes.size() == 1 ? " through-hole, " : " through-holes, ") +
                  "equivalent diameter ";
  for (std::size_t k = 0; k < h.holes.size() && k < 6; ++k) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%s%.1f", k ? ", " : "", h.holes[k].diameter * 1e3);
    s += buf;
  }
  return s + (h.holes.size() > 6 ? ", ... mm" : " mm");
}

// The holes' outlines as lines `width` pixels wide in colour (r, g, b), a hair behind the
// plate's rear extreme; `under` of them lie a hair further in, seen from the rear beneath
// the others.
vtkSmartPointer<vtkActor> outlineActor(const PlateHoles& h, double r, double g, double b,
                                       double width, bool under) {
  vtkNew<vtkPoints> pts;
  vtkNew<vtkCellArray> lines;
  const Vec3 shift = (h.rear - (under ? 0.04 : 0.05) * (h.front - h.rear)) * h.normal;
  for (const Hole& hole : h.holes) {
    const auto n = static_cast<vtkIdType>(hole.outline.size());
    if (n < 3) continue;
    lines->InsertNextCell(n + 1);
    const vtkIdType first = pts->GetNumberOfPoints();
    for (const Vec3& p : hole.outline) {
      const Vec3 q = p + shift;
      lines->InsertCellPoint(pts->InsertNextPoint(q.x(), q.y(), q.z()));
    }
    lines->InsertCellPoint(first);
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(pts);
  poly->SetLines(lines);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(poly);
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(r, g, b);
  actor->GetProperty()->SetLineWidth(width);
  actor->GetProperty()->LightingOff();
  return actor;
}

}  // namespace

std::vector<PlateImages> renderPlateImages(const std::string& run_dir, double time,
                                           const ImageOptions& options,
                                           const std::string& out_dir,
                                           const std::vector<int>& plates) {
  const RunInfo info = readRunInfo(run_dir);
  const RunStep step = readRunStep(run_dir, time);
  vtkUnstructuredGrid* grid = step.elements;
  vtkDataArray* bodies = grid->GetCellData()->GetArray("body");
  if (!bodies) throw RunError(run_dir + ": element series without a \"body\" array");
  vtkDataArray* field = grid->GetCellData()->GetArray(options.field.c_str());
  if (!field || field->GetNumberOfComponents() != 1) {
    std::string names;
    for (int a = 0; a < grid->GetCellData()->GetNumberOfArrays(); ++a)
      if (grid->GetCellData()->GetArray(a)->GetNumberOfComponents() == 1)
        names += std::string(names.empty() ? "" : ", ") + grid->GetCellData()->GetArrayName(a);
    throw UnknownField("no scalar cell field \"" + options.field +
                       "\" in the element series; have: " + names);
  }

  // Which bodies to draw: the caller's, or every body with cells or particles that is not a
  // projectile.
  std::vector<int> chosen = plates;
  if (chosen.empty()) {
    int max_body = -1;
    for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
      max_body = std::max(max_body, static_cast<int>(bodies->GetTuple1(c)));
    vtkDataArray* particle_bodies =
        step.particles ? step.particles->GetPointData()->GetArray("body") : nullptr;
    for (vtkIdType i = 0; particle_bodies && i < particle_bodies->GetNumberOfTuples(); ++i)
      max_body = std::max(max_body, static_cast<int>(particle_bodies->GetTuple1(i)));
    for (int b = 0; b <= max_body; ++b)
      if (b >= static_cast<int>(info.bodies.size()) || !info.bodies[b].projectile)
        chosen.push_back(b);
  }

  std::vector<PlateView> views;
  for (int b : chosen) {
    PlateView v;
    v.body = b;
    v.name = b < static_cast<int>(info.bodies.size()) && !info.bodies[b].name.empty()
                 ? info.bodies[b].name
                 : "body" + std::to_string(b);
    v.cells = extractBody(grid, b);
    if (v.cells->GetNumberOfCells() > 0) {
      v.holes = holesOf(v.cells, v.name, info.half);
    } else {  // made of particles: its plate proper drawn as the plate, the rest as debris
      const std::vector<vtkIdType> ids = particlesOf(step.particles, b);
      HoleOptions o;
      o.mirror = info.half;
      std::vector<int> proper;
      v.holes = findParticleHoles(plateParticles(step.particles, ids), o, &proper);
      v.holes.plate = v.name;
      for (int k : proper) v.particles.push_back(ids[static_cast<std::size_t>(k)]);
      if (v.particles.empty()) continue;  // nothing of it left to draw
    }
    views.push_back(std::move(v));
  }
  if (views.empty()) return {};

  // One camera extent for all plates, so their images compare at the same scale.
  const int W = options.width, H = options.height;
  const double vp_w = (kSceneViewport[2] - kSceneViewport[0]) * W;
  const double vp_h = (kSceneViewport[3] - kSceneViewport[1]) * H;
  // The plate proper's extent frames the views: loose pieces flying off do not widen them.
  double scale = 0;
  for (const PlateView& v : views)
    scale = std::max({scale, v.holes.halfV(), v.holes.halfU() * vp_h / vp_w});
  scale *= 1.04;
  const double pixel_size = 2 * scale / vp_h;

  // Colour range over all plates (damage: always [0, 1]).
  double unit = 1;
  const std::string bar_title = fieldTitle(options.field, &unit);
  vtkDataArray* particle_field =
      step.particles ? step.particles->GetPointData()->GetArray(options.field.c_str()) : nullptr;
  double lo = 1e300, hi = -1e300;
  for (const PlateView& v : views) {
    if (v.cells->GetNumberOfCells() > 0) {
      double r[2];
      v.cells->GetCellData()->GetArray(options.field.c_str())->GetRange(r);
      lo = std::min(lo, r[0] * unit);
      hi = std::max(hi, r[1] * unit);
    }
    for (std::size_t k = 0; particle_field && k < v.particles.size(); ++k) {
      lo = std::min(lo, particle_field->GetTuple1(v.particles[k]) * unit);
      hi = std::max(hi, particle_field->GetTuple1(v.particles[k]) * unit);
    }
  }
  if (options.field == "damage") lo = 0, hi = 1;
  if (options.field == "plastic_strain") lo = 0;
  const int labels = niceRange(lo, hi);
  const vtkSmartPointer<vtkLookupTable> lut = fieldColours(options.field, lo, hi, grid);

  std::vector<PlateImages> result;
  fs::create_directories(out_dir);
  for (const PlateView& v : views) {
    const PlateHoles& h = v.holes;
    vtkNew<vtkDataSetSurfaceFilter> surface;
    surface->SetInputData(v.cells);
    surface->Update();
    vtkPolyData* skin = surface->GetOutput();
    vtkNew<vtkDoubleArray> shown;  // the field in display units
    shown->SetName("shown");
    vtkDataArray* raw = skin->GetCellData()->GetArray(options.field.c_str());
    shown->SetNumberOfValues(raw ? raw->GetNumberOfTuples() : 0);
    for (vtkIdType c = 0; c < shown->GetNumberOfValues(); ++c)
      shown->SetValue(c, raw->GetTuple1(c) * unit);
    skin->GetCellData()->AddArray(shown);

    // The other particles in a slab of one plate extent on either side of the plate: other
    // bodies', and the plate's own that are not the plate proper (converted from its elements,
    // or failed and loose).
    std::vector<vtkIdType> keep;
    if (options.particles && step.particles) {
      std::vector<char> plate(static_cast<std::size_t>(step.particles->GetNumberOfPoints()), 0);
      for (vtkIdType i : v.particles) plate[static_cast<std::size_t>(i)] = 1;
      const double t = h.front - h.rear;
      for (vtkIdType i = 0; i < step.particles->GetNumberOfPoints(); ++i) {
        if (plate[static_cast<std::size_t>(i)]) continue;  // drawn as the plate
        Vec3 p;
        step.particles->GetPoint(i, p.data());
        const double s = (p - h.origin).dot(h.normal);
        if (s >= h.rear - t && s <= h.front + t) keep.push_back(i);
      }
    }
    // A plate made of particles colours them by the field, where the particles have it.
    std::string subtitle_front = bar_title;
    if (!v.particles.empty() && !particle_field)
      subtitle_front += " (not in the particle series: particles in their body's colour)";

    PlateImages images;
    images.plate = v.name;
    images.body = v.body;
    images.time = step.time;
    images.pixel_size = pixel_size;
    images.holes = h;
    images.particles = v.particles;
    for (int side = 0; side < 2; ++side) {
      const bool rear = side == 1;
      OffscreenWindow win(W, H);
      Page page = makePage(win.window(), W, H);

      const vtkSmartPointer<vtkPolyDataMapper> mapper = fieldMapper(skin, lut);
      const int copies = !v.particles.empty() ? 0 : info.half ? 2 : 1;  // of its elements
      for (int m = 0; m < copies; ++m) {
        vtkNew<vtkActor> actor;
        actor->SetMapper(mapper);
        actor->GetProperty()->SetAmbient(0.25);
        actor->GetProperty()->SetDiffuse(0.8);
        if (m == 1) actor->SetScale(1, -1, 1);  // the mirror image of a half model
        page.scene->AddActor(actor);
      }
      if (auto plate = particleActor(step.particles, v.particles, lut, options.field, unit,
                                     info.half))
        page.scene->AddActor(plate);
      if (auto particles = particleActor(step.particles, keep, nullptr, "", 1.0, info.half))
        page.scene->AddActor(particles);

      vtkCamera* cam = page.scene->GetActiveCamera();
      cam->ParallelProjectionOn();
      const double far = 10 * (scale + (h.front - h.rear));
      const Vec3 centre = h.extentCentre();
      const Vec3 eye = centre + (rear ? -far : far) * h.normal;
      cam->SetFocalPoint(centre.x(), centre.y(), centre.z());
      cam->SetPosition(eye.x(), eye.y(), eye.z());
      cam->SetViewUp(h.v.x(), h.v.y(), h.v.z());
      cam->SetParallelScale(scale);
      page.scene->ResetCameraClippingRange();
      // The hole outlines in a layer over the scene, seen over the debris flying behind the
      // plate (which hid them in the scene), with a copy of its camera.
      vtkNew<vtkRenderer> outlines;
      vtkNew<vtkCamera> outline_camera;
      if (rear && options.hole_outlines && !h.holes.empty()) {
        outlines->SetViewport(kSceneViewport[0], kSceneViewport[1], kSceneViewport[2],
                              kSceneViewport[3]);
        outlines->SetLayer(1);
        outline_camera->DeepCopy(cam);
        outlines->SetActiveCamera(outline_camera);
        // red on a white border: seen on red debris (the projectile's colour) as well
        outlines->AddActor(outlineActor(h, 1.0, 1.0, 1.0, 7.0, true));
        outlines->AddActor(outlineActor(h, 0.89, 0.10, 0.11, 3.0, false));
        outlines->ResetCameraClippingRange();
        win.window()->SetNumberOfLayers(2);
        win.window()->AddRenderer(outlines);
      }

      addTitle(page, v.name + (rear ? ": rear face" : ": front face"),
               timeLabel(step.time) + "   |   " + (rear ? holeSummary(h) : subtitle_front));
      addScaleBar(page, pixel_size);
      addScalarBar(page, lut, bar_title, labels);

      const std::string png =
          (fs::path(out_dir) / (v.name + (rear ? "_rear.png" : "_front.png"))).string();
      win.writePng(png);
      (rear ? images.rear_png : images.front_png) = png;
    }
    result.push_back(std::move(images));
  }
  return result;
}

}  // namespace fesph
