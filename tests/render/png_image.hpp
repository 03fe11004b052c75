// SPDX-License-Identifier: MIT
// A PNG read back as RGB pixels, and the colour tests the image tests share.
#pragma once

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

namespace fesph::testing {

/// RGB pixels of a PNG, row 0 at the bottom (VTK's image order).
struct Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
  const unsigned char* at(int x, int y) const {
    return &rgb[3 * (static_cast<std::size_t>(y) * width + x)];
  }
  /// Pixels for which f holds in the box [x0, x1] x [y0, y1] (clipped to the image).
  std::size_t count(const std::function<bool(const unsigned char*)>& f, int x0 = 0, int y0 = 0,
                    int x1 = -1, int y1 = -1) const {
    if (x1 < 0) x1 = width - 1;
    if (y1 < 0) y1 = height - 1;
    std::size_t n = 0;
    for (int y = std::max(0, y0); y <= std::min(height - 1, y1); ++y)
      for (int x = std::max(0, x0); x <= std::min(width - 1, x1); ++x) n += f(at(x, y));
    return n;
  }
};

inline Image readPng(const std::string& path) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* img = reader->GetOutput();
  Image out;
  int dims[3];
  img->GetDimensions(dims);
  out.width = dims[0];
  out.height = dims[1];
  const int nc = img->GetNumberOfScalarComponents();
  const auto* p = static_cast<const unsigned char*>(img->GetScalarPointer());
  for (int i = 0; i < out.width * out.height; ++i)
    for (int c = 0; c < 3; ++c) out.rgb.push_back(p[i * nc + c]);
  return out;
}

inline bool white(const unsigned char* p) { return p[0] > 245 && p[1] > 245 && p[2] > 245; }

/// Every channel within tol of q's.
inline bool near(const unsigned char* p, const unsigned char* q, int tol) {
  return std::abs(p[0] - q[0]) <= tol && std::abs(p[1] - q[1]) <= tol &&
         std::abs(p[2] - q[2]) <= tol;
}

}  // namespace fesph::testing
