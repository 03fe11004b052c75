// SPDX-License-Identifier: MIT
// Section view: cut every body with the plane y = 0 (just inside the half model's face) and look
// at the section polygons with an orthographic camera from -y.
#include "render/section_view.hpp"

#include "core/common/error.hpp"
#include "render/osmesa_context.hpp"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkCutter.h>
#include <vtkDoubleArray.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPlane.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <cmath>

namespace fesph {

using namespace render_detail;

std::string renderSectionView(const std::string& run_dir, double time, const ImageOptions& options,
                              const std::string& out_png) {
  const RunInfo info = readRunInfo(run_dir);
  const RunStep step = readRunStep(run_dir, time);
  // Damage is the plate images' default; the section shows plastic strain unless asked otherwise.
  const std::string field = options.field == "damage" ? "plastic_strain" : options.field;
  vtkDataArray* values = step.elements->GetCellData()->GetArray(field.c_str());
  if (!values || values->GetNumberOfComponents() != 1)
    throw RunError("no scalar cell field \"" + field + "\" in the element series of " + run_dir);

  // A half model's nodes lie exactly on y = 0, where a cut is ill-posed: cut a hair inside.
  double bounds[6];
  step.elements->GetBounds(bounds);
  const double diagonal =
      std::sqrt(std::pow(bounds[1] - bounds[0], 2) + std::pow(bounds[3] - bounds[2], 2) +
                std::pow(bounds[5] - bounds[4], 2));
  vtkNew<vtkPlane> plane;
  plane->SetOrigin(0, info.half ? 1e-6 * diagonal : 0.0, 0);
  plane->SetNormal(0, 1, 0);
  vtkNew<vtkCutter> cutter;  // passes the cell data of the cut cells to the section polygons
  cutter->SetCutFunction(plane);
  cutter->SetInputData(step.elements);
  cutter->GenerateTrianglesOff();
  cutter->Update();
  vtkPolyData* skin = cutter->GetOutput();
  if (skin->GetNumberOfCells() == 0)
    throw RunError(run_dir + ": nothing of the model lies on the plane y = 0");

  double unit = 1;
  const std::string bar_title = fieldTitle(field, &unit);
  vtkNew<vtkDoubleArray> shown;
  shown->SetName("shown");
  vtkDataArray* raw = skin->GetCellData()->GetArray(field.c_str());
  shown->SetNumberOfValues(raw->GetNumberOfTuples());
  for (vtkIdType c = 0; c < raw->GetNumberOfTuples(); ++c) shown->SetValue(c, raw->GetTuple1(c) * unit);
  skin->GetCellData()->AddArray(shown);

  // Particles whose centre lies within 1.5 radii of the plane.
  std::vector<vtkIdType> keep;
  if (options.particles && step.particles) {
    vtkDataArray* radius = step.particles->GetPointData()->GetArray("radius");
    for (vtkIdType i = 0; radius && i < step.particles->GetNumberOfPoints(); ++i)
      if (std::abs(step.particles->GetPoint(i)[1]) <= 1.5 * radius->GetTuple1(i)) keep.push_back(i);
  }

  // The colours' range holds the elements' values and those of the particles drawn.
  double range[2];
  values->GetRange(range);
  double lo = range[0] * unit, hi = range[1] * unit;
  vtkDataArray* particle_values =
      step.particles ? step.particles->GetPointData()->GetArray(field.c_str()) : nullptr;
  for (std::size_t k = 0; particle_values && k < keep.size(); ++k) {
    lo = std::min(lo, particle_values->GetTuple1(keep[k]) * unit);
    hi = std::max(hi, particle_values->GetTuple1(keep[k]) * unit);
  }
  if (field == "plastic_strain") lo = 0;
  const int labels = niceRange(lo, hi);
  const vtkSmartPointer<vtkLookupTable> lut = fieldColours(field, lo, hi, step.elements);

  const int W = options.width, H = options.height;
  OffscreenWindow win(W, H);
  Page page = makePage(win.window(), W, H);
  const vtkSmartPointer<vtkPolyDataMapper> mapper = fieldMapper(skin, lut);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetAmbient(0.25);
  actor->GetProperty()->SetDiffuse(0.8);
  page.scene->AddActor(actor);
  if (auto particles = particleActor(step.particles, keep, lut, field, unit)) page.scene->AddActor(particles);

  // Fit the x-z extent of the cut elements and of the particles drawn near them; x is up,
  // -z (flight) to the right. Debris that has flown further than half the elements' extent
  // beyond them is left out of the frame: one stray particle a metre away would otherwise
  // shrink the plates to a few pixels.
  double b[6];
  skin->GetBounds(b);
  // Only x and z (0 and 2) frame the picture; the cut is flat in y.
  const double margin_x = 0.5 * (b[1] - b[0]), margin_z = 0.5 * (b[5] - b[4]);
  const double lo_x = b[0] - margin_x, hi_x = b[1] + margin_x;
  const double lo_z = b[4] - margin_z, hi_z = b[5] + margin_z;
  for (vtkIdType i : keep) {
    const double* x = step.particles->GetPoint(i);
    if (x[0] < lo_x || x[0] > hi_x || x[2] < lo_z || x[2] > hi_z) continue;
    b[0] = std::min(b[0], x[0]), b[1] = std::max(b[1], x[0]);
    b[4] = std::min(b[4], x[2]), b[5] = std::max(b[5], x[2]);
  }
  const double vp_w = (kSceneViewport[2] - kSceneViewport[0]) * W;
  const double vp_h = (kSceneViewport[3] - kSceneViewport[1]) * H;
  const double half_x = 0.5 * (b[1] - b[0]), half_z = 0.5 * (b[5] - b[4]);
  const double scale = 1.04 * std::max(half_x, half_z * vp_h / vp_w);
  const double cx = 0.5 * (b[0] + b[1]), cz = 0.5 * (b[4] + b[5]);
  vtkCamera* cam = page.scene->GetActiveCamera();
  cam->ParallelProjectionOn();
  cam->SetFocalPoint(cx, 0, cz);
  cam->SetPosition(cx, -10 * (scale + b[3] - b[2]), cz);
  cam->SetViewUp(1, 0, 0);
  cam->SetParallelScale(scale);
  page.scene->ResetCameraClippingRange();

  addTitle(page, "Section on the symmetry plane y = 0", timeLabel(step.time) + "   |   " + bar_title);
  addScaleBar(page, 2 * scale / vp_h);
  addScalarBar(page, lut, bar_title, labels);
  win.writePng(out_png);
  return out_png;
}

}  // namespace fesph
