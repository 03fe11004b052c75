// SPDX-License-Identifier: MIT
// OffscreenWindow: OSMesa core-profile 3.2 context + vtkGenericOpenGLRenderWindow, read back
// with vtkWindowToImageFilter and written with vtkPNGWriter.
#include "render/osmesa_context.hpp"

#include "core/common/error.hpp"
#include "render/vtk_errors.hpp"

#include <GL/osmesa.h>

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkWindowToImageFilter.h>

#include <filesystem>
#include <vector>

namespace fesph {

namespace detail {
int glxShimAnchor();  // render/glx_shim.cpp
}

struct OffscreenWindow::Impl {
  OSMesaContext context = nullptr;
  std::vector<unsigned char> buffer;
  vtkNew<vtkGenericOpenGLRenderWindow> window;
  vtkNew<vtkCallbackCommand> make_current;
  vtkNew<vtkCallbackCommand> is_current;
  int width = 0, height = 0;

  void makeCurrent() {
    OSMesaMakeCurrent(context, buffer.data(), GL_UNSIGNED_BYTE, width, height);
  }
};

OffscreenWindow::OffscreenWindow(int width, int height)
    : impl_(std::make_unique<Impl>()), width_(width), height_(height) {
  if (detail::glxShimAnchor() != 1) throw RunError("GLX shim not linked");
  if (width < 16 || height < 16)
    throw RunError("image size " + std::to_string(width) + "x" + std::to_string(height) +
                   " is too small");
  Impl& w = *impl_;
  const int attribs[] = {OSMESA_FORMAT,
                         OSMESA_RGBA,
                         OSMESA_DEPTH_BITS,
                         24,
                         OSMESA_STENCIL_BITS,
                         8,
                         OSMESA_ACCUM_BITS,
                         0,
                         OSMESA_PROFILE,
                         OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION,
                         3,
                         OSMESA_CONTEXT_MINOR_VERSION,
                         2,
                         0};
  w.context = OSMesaCreateContextAttribs(attribs, nullptr);
  if (!w.context) throw RunError("OSMesa: cannot create an OpenGL 3.2 core profile context");
  w.width = width;
  w.height = height;
  w.buffer.assign(static_cast<std::size_t>(width) * height * 4, 0);
  w.makeCurrent();

  // VTK asks the generic window to make itself current; keep the OSMesa context bound.
  w.make_current->SetClientData(&w);
  w.make_current->SetCallback([](vtkObject*, unsigned long, void* data, void*) {
    static_cast<Impl*>(data)->makeCurrent();
  });
  w.is_current->SetCallback([](vtkObject*, unsigned long, void*, void* call_data) {
    *static_cast<bool*>(call_data) = true;
  });
  w.window->AddObserver(vtkCommand::WindowMakeCurrentEvent, w.make_current);
  w.window->AddObserver(vtkCommand::WindowIsCurrentEvent, w.is_current);

  w.window->SetSize(width, height);
  w.window->SetOffScreenRendering(1);
  w.window->SetIsCurrent(true);
  w.window->SetReadyForRendering(true);
  w.window->SetSupportsOpenGL(true);
  w.window->SetFrameBlitModeToNoBlit();
  w.window->SetMultiSamples(0);
}

OffscreenWindow::~OffscreenWindow() {
  // Release the GL objects while their context is still current.
  impl_->makeCurrent();
  impl_->window->Finalize();
  OSMesaDestroyContext(impl_->context);
}

vtkRenderWindow* OffscreenWindow::window() const { return impl_->window; }

void OffscreenWindow::writePng(const std::string& path) {
  impl_->makeCurrent();
  impl_->window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(impl_->window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();

  const std::filesystem::path target(path);
  if (target.has_parent_path()) std::filesystem::create_directories(target.parent_path());
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputConnection(grab->GetOutputPort());
  writer->SetFileName(path.c_str());
  clearVtkError();
  writer->Write();
  if (writer->GetErrorCode() != 0 || !std::filesystem::exists(target))
    throw RunError(cannotWrite("image " + path, writer->GetErrorCode()));
}

}  // namespace fesph
