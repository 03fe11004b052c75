// SPDX-License-Identifier: MIT
// Velocity history plot: history.csv columns -> vtkTable -> vtkChartXY lines, drawn by a
// vtkContextActor on the OSMesa window.
#include "render/velocity_plot.hpp"

#include "core/common/error.hpp"
#include "render/osmesa_context.hpp"

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextActor.h>
#include <vtkContextDevice2D.h>
#include <vtkContextScene.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkRect.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fesph {

namespace render_detail {

std::vector<std::string> plottedBodies(const std::string& csv) {
  const RunInfo info = readRunInfo(std::filesystem::path(csv).parent_path().string());
  std::vector<std::string> out;
  for (const RunBody& b : info.bodies)
    if (b.projectile) out.push_back(b.name);
  if (out.empty() && !info.bodies.empty()) out.push_back(info.bodies.front().name);
  return out;
}

VelocitySeries readVelocity(const std::string& csv, std::string body, VelocityMeasure measure) {
  std::ifstream in(csv);
  if (!in) throw RunError("cannot read " + csv);
  if (body.empty()) {
    const std::vector<std::string> bodies = plottedBodies(csv);
    if (!bodies.empty()) body = bodies.front();
  }
  std::string line;
  std::getline(in, line);
  std::vector<std::string> cols;
  {
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cols.push_back(c);
  }
  const auto column = [&](const std::string& name) {
    const auto it = std::find(cols.begin(), cols.end(), name);
    if (it == cols.end()) throw RunError(csv + ": no column \"" + name + "\"");
    return static_cast<std::size_t>(it - cols.begin());
  };
  const std::size_t it = column("time"), ix = column(body + "_vx"), iy = column(body + "_vy"),
                    iz = column(body + "_vz");
  VelocitySeries s;
  std::vector<double> row;
  while (std::getline(in, line)) {
    row.clear();
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) row.push_back(std::strtod(c.c_str(), nullptr));
    if (row.size() < cols.size()) continue;  // a row cut short by a stopped run
    const double vx = row[ix], vy = row[iy], vz = row[iz];
    s.t_us.push_back(row[it] * 1e6);
    s.v.push_back(measure == VelocityMeasure::Speed ? std::sqrt(vx * vx + vy * vy + vz * vz)
                                                    : -vz);
  }
  if (s.t_us.empty()) throw RunError(csv + ": no rows");
  return s;
}

}  // namespace render_detail

namespace {

void styleAxis(vtkAxis* axis, const std::string& title, int font) {
  axis->SetTitle(title);
  axis->GetTitleProperties()->SetFontSize(font);
  axis->GetTitleProperties()->SetColor(0.1, 0.1, 0.1);
  axis->GetTitleProperties()->BoldOn();
  axis->GetLabelProperties()->SetFontSize(font * 5 / 6);
  axis->GetLabelProperties()->SetColor(0.1, 0.1, 0.1);
  axis->GetGridPen()->SetColor(215, 215, 215);
}

}  // namespace

void curveColour(int k, unsigned char rgb[3]) {
  // Tableau 10: distinct, print-friendly line colours.
  static const unsigned char palette[8][3] = {{31, 119, 180}, {255, 127, 14}, {44, 160, 44},
                                              {214, 39, 40},  {148, 103, 189}, {140, 86, 75},
                                              {227, 119, 194}, {127, 127, 127}};
  for (int c = 0; c < 3; ++c) rgb[c] = palette[k % 8][c];
}

std::string renderVelocityPlot(
    const std::vector<std::pair<std::string, std::string>>& label_and_history_csv,
    const std::string& body, const std::string& out_png, const ImageOptions& options,
    VelocityMeasure measure) {
  if (label_and_history_csv.empty()) throw RunError("velocity plot: no history to draw");
  const int W = options.width, H = options.height;
  OffscreenWindow win(W, H);
  // Charts draw through the context device of VTK::RenderingContextOpenGL2; without its
  // object factory the chart silently renders nothing.
  if (vtkSmartPointer<vtkContextDevice2D>::Take(vtkContextDevice2D::New()) == nullptr)
    throw RunError("velocity plot: VTK::RenderingContextOpenGL2 is not initialised");

  // A context actor in a plain renderer: a vtkContextView would also build an interactor.
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1, 1, 1);
  win.window()->AddRenderer(renderer);
  vtkNew<vtkContextActor> actor;
  renderer->AddActor(actor);
  vtkNew<vtkChartXY> chart;
  actor->GetScene()->AddItem(chart);
  const int font = std::max(10, H / 40);
  chart->SetTitle(measure == VelocityMeasure::Speed ? "Projectile velocity"
                                                    : "Projectile velocity along -z");
  chart->GetTitleProperties()->SetFontSize(font * 6 / 5);
  chart->GetTitleProperties()->BoldOn();
  chart->GetTitleProperties()->SetColor(0.1, 0.1, 0.1);
  styleAxis(chart->GetAxis(vtkAxis::BOTTOM), "Time (\u00b5s)", font);
  styleAxis(chart->GetAxis(vtkAxis::LEFT),
            measure == VelocityMeasure::Speed ? "Velocity (m/s)" : "-v_z (m/s)", font);

  // One curve per run, or per projectile of a run that has several, each labelled by name.
  std::vector<std::pair<std::string, render_detail::VelocitySeries>> curves;
  for (const auto& [label, csv] : label_and_history_csv) {
    std::vector<std::string> bodies = {body};
    if (body.empty()) {
      bodies = render_detail::plottedBodies(csv);
      if (bodies.empty()) bodies = {""};  // readVelocity says what is missing
    }
    for (const std::string& b : bodies)
      curves.emplace_back(bodies.size() > 1 ? label + ": " + b : label,
                          render_detail::readVelocity(csv, b, measure));
  }
  double vmin = 0, vmax = 0;
  for (std::size_t k = 0; k < curves.size(); ++k) {
    const auto& [label, s] = curves[k];
    vtkNew<vtkTable> table;
    vtkNew<vtkDoubleArray> t, v;
    t->SetName("time");
    v->SetName(label.c_str());
    for (std::size_t i = 0; i < s.t_us.size(); ++i) {
      t->InsertNextValue(s.t_us[i]);
      v->InsertNextValue(s.v[i]);
      vmin = std::min(vmin, s.v[i]);
      vmax = std::max(vmax, s.v[i]);
    }
    table->AddColumn(t);
    table->AddColumn(v);
    vtkPlot* line = chart->AddPlot(vtkChart::LINE);
    line->SetInputData(table, 0, 1);
    unsigned char c[3];
    curveColour(static_cast<int>(k), c);
    line->SetColor(c[0], c[1], c[2], 255);
    line->SetWidth(std::max(2.0f, H / 300.0f));
  }
  // Velocity from zero, so a residual velocity reads as a fraction of the impact velocity.
  vtkAxis* left = chart->GetAxis(vtkAxis::LEFT);
  left->SetBehavior(vtkAxis::FIXED);
  left->SetRange(vmin < 0 ? 1.08 * vmin : 0.0, vmax > 0 ? 1.08 * vmax : 1.0);

  // Room for the axis titles, the last tick label and the chart title.
  chart->SetAutoSize(false);
  chart->SetSize(vtkRectf(0.01f * W, 0.01f * H, 0.96f * W, 0.96f * H));
  chart->SetShowLegend(true);
  vtkChartLegend* legend = chart->GetLegend();
  legend->SetHorizontalAlignment(vtkChartLegend::RIGHT);
  legend->SetVerticalAlignment(vtkChartLegend::TOP);
  legend->SetLabelSize(font * 11 / 10);
  legend->GetLabelProperties()->SetColor(0.1, 0.1, 0.1);
  legend->SetSymbolWidth(std::max(25, W / 40));

  win.writePng(out_png);
  return out_png;
}

}  // namespace fesph
