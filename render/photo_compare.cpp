// SPDX-License-Identifier: MIT
// Photographs in and comparison images out, through VTK's image readers and PNG writer.
#include "render/photo_compare.hpp"

#include "core/common/error.hpp"
#include "core/common/number_text.hpp"
#include "render/plate_images.hpp"
#include "render/vtk_errors.hpp"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkImageReader2.h>
#include <vtkImageReader2Factory.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>

namespace fesph {

namespace {

/// 8-bit RGB pixels, row 0 at the top.
struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  RgbImage(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 255) {}
  void set(int i, int j, std::array<std::uint8_t, 3> c) {
    std::copy(c.begin(), c.end(), rgb.begin() + 3 * (static_cast<std::ptrdiff_t>(j) * width + i));
  }
};

void writePng(const std::uint8_t* pixels, int width, int height, int components,
              const std::string& path) {
  vtkNew<vtkImageData> img;
  img->SetDimensions(width, height, 1);
  img->AllocateScalars(VTK_UNSIGNED_CHAR, components);
  auto* out = static_cast<std::uint8_t*>(img->GetScalarPointer());
  const std::size_t row = static_cast<std::size_t>(width) * components;
  for (int j = 0; j < height; ++j)  // VTK's row 0 is the bottom one
    std::copy(pixels + j * row, pixels + (j + 1) * row, out + (height - 1 - j) * row);
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent);
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputData(img);
  writer->SetFileName(path.c_str());
  clearVtkError();
  writer->Write();
  if (writer->GetErrorCode() != 0) throw RunError(cannotWrite(path, writer->GetErrorCode()));
}

std::uint8_t grey8(float v) { return static_cast<std::uint8_t>(std::clamp(v, 0.0f, 1.0f) * 255 + 0.5f); }

// Pixels in a hole of `label` (> 0) with a 4-neighbour outside every hole: the outline drawn
// on the images.
bool onEdge(const std::vector<int>& label, int w, int h, int i, int j) {
  const auto at = [&](int a, int b) {
    return a >= 0 && b >= 0 && a < w && b < h && label[static_cast<std::size_t>(b) * w + a] > 0;
  };
  return at(i, j) && !(at(i - 1, j) && at(i + 1, j) && at(i, j - 1) && at(i, j + 1));
}

// An outline two pixels wide, so it stays visible on large photographs viewed small.
bool nearEdge(const std::vector<int>& label, int w, int h, int i, int j) {
  return onEdge(label, w, h, i, j) || (i > 0 && onEdge(label, w, h, i - 1, j)) ||
         (j > 0 && onEdge(label, w, h, i, j - 1));
}

}  // namespace

GrayImage readPhoto(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path, 0, 0, "no such photograph");
  vtkNew<vtkImageReader2Factory> factory;
  vtkSmartPointer<vtkImageReader2> reader;
  reader.TakeReference(factory->CreateImageReader2(path.c_str()));
  if (!reader)
    throw InputError(path, 0, 0, "not an image format VTK reads (PNG, JPEG, TIFF, BMP, PNM)");
  reader->SetFileName(path.c_str());
  clearVtkError();
  reader->Update();
  vtkImageData* img = reader->GetOutput();
  int dims[3];
  img->GetDimensions(dims);
  const int nc = img->GetNumberOfScalarComponents();
  if (reader->GetErrorCode() != 0 || !vtkError().empty() || dims[0] < 3 || dims[1] < 3 ||
      nc < 1) {
    const std::string cause = vtkCause(reader->GetErrorCode());
    throw InputError(path, 0, 0, "cannot read the image" + (cause.empty() ? "" : ": " + cause));
  }
  const double full = img->GetScalarTypeMax();
  GrayImage out{dims[0], dims[1], std::vector<float>(static_cast<std::size_t>(dims[0]) * dims[1])};
  for (int j = 0; j < dims[1]; ++j)
    for (int i = 0; i < dims[0]; ++i) {
      const int y = dims[1] - 1 - j;  // VTK's row 0 is the bottom one
      double v = img->GetScalarComponentAsDouble(i, y, 0, 0);
      if (nc >= 3)
        v = 0.299 * v + 0.587 * img->GetScalarComponentAsDouble(i, y, 0, 1) +
            0.114 * img->GetScalarComponentAsDouble(i, y, 0, 2);
      out.value[static_cast<std::size_t>(j) * dims[0] + i] = static_cast<float>(v / full);
    }
  return out;
}

void writeGrayPng(const GrayImage& image, const std::string& path) {
  std::vector<std::uint8_t> px(image.value.size());
  std::transform(image.value.begin(), image.value.end(), px.begin(), grey8);
  writePng(px.data(), image.width, image.height, 1, path);
}

SimulatedPlate readSimulatedPlate(const std::string& run_dir, double time, int body,
                                  const std::string& name, bool half, double* step_time) {
  const render_detail::RunStep step = render_detail::readRunStep(run_dir, time);
  vtkUnstructuredGrid* grid = step.elements;
  vtkDataArray* bodies = grid->GetCellData()->GetArray("body");
  if (!bodies) throw RunError(run_dir + ": element series without a \"body\" array");
  std::vector<Vec3> x(static_cast<std::size_t>(grid->GetNumberOfPoints()));
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) grid->GetPoint(i, x[i].data());
  std::vector<std::array<int, 4>> tets;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    if (static_cast<int>(bodies->GetTuple1(c)) != body) continue;
    grid->GetCellPoints(c, ids);
    if (ids->GetNumberOfIds() != 4) continue;
    tets.push_back({static_cast<int>(ids->GetId(0)), static_cast<int>(ids->GetId(1)),
                    static_cast<int>(ids->GetId(2)), static_cast<int>(ids->GetId(3))});
  }
  HoleOptions options;
  options.mirror = half;  // the half model's symmetry plane is y = 0
  if (step_time) *step_time = step.time;
  if (!tets.empty()) return simulatedPlate(x, tets, options);
  // A plate made of particles: its particles.
  const std::vector<vtkIdType> particles = render_detail::particlesOf(step.particles, body);
  if (particles.empty())
    throw RunError(run_dir + ": plate '" + name + "' has neither a live element nor a particle "
                   "at t = " + shortestText(step.time) + " s");
  return simulatedParticlePlate(render_detail::plateParticles(step.particles, particles), options);
}

void writeSideBySide(const GrayImage& photo, const PhotoSegmentation& seg,
                     const HoleComparison& cmp, const SimulatedPlate& plate,
                     const std::string& path) {
  const int w = photo.width, h = photo.height, gap = std::max(8, w / 50);
  RgbImage out(2 * w + gap, h);
  // The simulated plate's extent on the photograph's grid.
  const Eigen::Vector2d a = cmp.frame.toPixel(-plate.half_size);
  const Eigen::Vector2d b = cmp.frame.toPixel(plate.half_size);
  const Eigen::Vector2d lo = a.cwiseMin(b), hi = a.cwiseMax(b);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const std::size_t p = static_cast<std::size_t>(j) * w + i;
      const std::uint8_t g = grey8(photo.value[p]);
      out.set(i, j, nearEdge(seg.label, w, h, i, j) ? std::array<std::uint8_t, 3>{228, 26, 28}
                                                   : std::array<std::uint8_t, 3>{g, g, g});
      const bool inside = i + 0.5 >= lo.x() && i + 0.5 < hi.x() && j + 0.5 >= lo.y() && j + 0.5 < hi.y();
      std::array<std::uint8_t, 3> s = inside ? std::array<std::uint8_t, 3>{190, 190, 190}
                                             : std::array<std::uint8_t, 3>{70, 70, 70};
      if (cmp.simulated_label[p] > 0) s = {15, 15, 15};
      if (nearEdge(cmp.simulated_label, w, h, i, j)) s = {31, 120, 230};
      out.set(w + gap + i, j, s);
    }
  writePng(out.rgb.data(), out.width, out.height, 3, path);
}

void writeOverlay(const GrayImage& photo, const PhotoSegmentation& seg, const HoleComparison& cmp,
                  const std::string& path) {
  const int w = photo.width, h = photo.height;
  RgbImage out(w, h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const std::size_t p = static_cast<std::size_t>(j) * w + i;
      const float g = 0.35f + 0.5f * std::clamp(photo.value[p], 0.0f, 1.0f);  // dimmed, never black
      std::array<float, 3> c = {g, g, g};
      const bool in_photo = seg.label[p] > 0, in_sim = cmp.simulated_label[p] > 0;
      if (in_photo || in_sim) {
        const std::array<float, 3> tint = in_photo && in_sim ? std::array<float, 3>{0.10f, 0.70f, 0.15f}
                                          : in_photo         ? std::array<float, 3>{0.89f, 0.10f, 0.11f}
                                                             : std::array<float, 3>{0.12f, 0.47f, 0.90f};
        for (int k = 0; k < 3; ++k) c[k] = 0.25f * c[k] + 0.75f * tint[k];
      }
      out.set(i, j, {grey8(c[0]), grey8(c[1]), grey8(c[2])});
    }
  writePng(out.rgb.data(), out.width, out.height, 3, path);
}

}  // namespace fesph
