// SPDX-License-Identifier: MIT
// Off-screen OpenGL rendering without an X display: an OSMesa core-profile context driving a
// vtkGenericOpenGLRenderWindow (recipe: shared/reference/vtk-osmesa.md, docs/rendering.md).
#pragma once

#include <memory>
#include <string>

class vtkRenderWindow;

namespace fesph {

/// An OSMesa context made current on a client RGBA buffer, and a VTK render window that draws
/// into it. One window may exist at a time (OSMesa contexts are current per thread). Create it
/// before the renderers and actors that use it, so it is destroyed after them.
class OffscreenWindow {
 public:
  /// Throws RunError when OSMesa cannot create a context.
  OffscreenWindow(int width, int height);
  ~OffscreenWindow();
  OffscreenWindow(const OffscreenWindow&) = delete;
  OffscreenWindow& operator=(const OffscreenWindow&) = delete;

  /// The render window: add renderers to it, or hand it to a vtkContextView.
  vtkRenderWindow* window() const;
  int width() const { return width_; }
  int height() const { return height_; }

  /// Render and write the image to `path` (PNG, parent folder created). Throws RunError.
  void writePng(const std::string& path);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int width_, height_;
};

}  // namespace fesph
