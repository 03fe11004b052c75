// SPDX-License-Identifier: MIT
// GLX entry points that let Debian's GLX-only GLEW start up on an OSMesa context: exported from
// the executable, they interpose libGLX's (shared/reference/vtk-osmesa.md, step 3).
#include <GL/osmesa.h>

#include <cstring>

namespace {

using GlxProc = void (*)();

// GLEW only checks that a display is current; it never dereferences it.
char dummy_display;
void* currentDisplay() { return &dummy_display; }

GlxProc procAddress(const unsigned char* name) {
  const char* n = reinterpret_cast<const char*>(name);
  if (std::strcmp(n, "glXGetCurrentDisplay") == 0)
    return reinterpret_cast<GlxProc>(&currentDisplay);
  return reinterpret_cast<GlxProc>(OSMesaGetProcAddress(n));
}

}  // namespace

// Signatures as in <GL/glx.h>, with Display* as void* (C linkage: only the names link).
extern "C" {
__attribute__((visibility("default"))) GlxProc glXGetProcAddressARB(const unsigned char* name) {
  return procAddress(name);
}
__attribute__((visibility("default"))) GlxProc glXGetProcAddress(const unsigned char* name) {
  return procAddress(name);
}
__attribute__((visibility("default"))) int glXQueryVersion(void*, int* major, int* minor) {
  if (major) *major = 1;
  if (minor) *minor = 4;
  return 1;
}
__attribute__((visibility("default"))) const char* glXGetClientString(void*, int) { return ""; }
__attribute__((visibility("default"))) const char* glXQueryExtensionsString(void*, int) {
  return "";
}
}

namespace fesph::detail {
// Referenced by OffscreenWindow so that a static link always pulls this object file in.
int glxShimAnchor() { return 1; }
}  // namespace fesph::detail
