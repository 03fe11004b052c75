// SPDX-License-Identifier: MIT
#include "render/vtk_errors.hpp"

#include <cerrno>
#include <cstring>

#include <vtkErrorCode.h>
#include <vtkLogger.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkSmartPointer.h>

namespace fesph {

namespace {

/// An output window that keeps the first error since it was cleared and prints nothing.
/// VTK's I/O is driven from serial code only, so one window serves the process.
class KeptErrors : public vtkOutputWindow {
 public:
  static KeptErrors* New();
  vtkTypeMacro(KeptErrors, vtkOutputWindow);
  void DisplayErrorText(const char* text) override {
    if (first.empty() && text) first = text;
  }
  void DisplayText(const char*) override {}
  void DisplayWarningText(const char*) override {}
  void DisplayGenericWarningText(const char*) override {}
  void DisplayDebugText(const char*) override {}
  std::string first;
};
vtkStandardNewMacro(KeptErrors);

KeptErrors* g_kept = nullptr;

std::string failed(const char* what, const std::string& path, unsigned long error_code) {
  const std::string cause = vtkCause(error_code);
  return std::string(what) + " " + path + (cause.empty() ? "" : ": " + cause);
}

}  // namespace

std::string vtkFailure(unsigned long error_code) {
  switch (error_code) {
    case vtkErrorCode::NoError: return "";
    case vtkErrorCode::OutOfDiskSpaceError: return "the disk is full";
    case vtkErrorCode::FileNotFoundError: return "no such file";
    case vtkErrorCode::CannotOpenFileError:
      return "cannot open it (no such folder, or no permission)";
    case vtkErrorCode::PrematureEndOfFileError: return "the file ends early (cut short?)";
    case vtkErrorCode::FileFormatError:
    case vtkErrorCode::UnrecognizedFileTypeError: return "not a file of the expected format";
    default:
      // Below VTK's own codes the code is the system's errno (the XML writers pass it on).
      if (error_code == ENOSPC) return "the disk is full";
      if (error_code < vtkErrorCode::FirstVTKErrorCode)
        return std::strerror(static_cast<int>(error_code));
      return std::string("VTK error ") + vtkErrorCode::GetStringFromErrorCode(error_code);
  }
}

void quietVtk() {
  static vtkSmartPointer<KeptErrors> window = vtkSmartPointer<KeptErrors>::New();
  vtkOutputWindow::SetInstance(window);
  g_kept = window;
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);  // the coloured copy of each message
}

void clearVtkError() {
  if (g_kept) g_kept->first.clear();
}

std::string vtkError() {
  if (!g_kept) return "";
  // "ERROR: In FILE, line N\nCLASS (0xADDRESS): message\n\n": the message's first line
  std::string text = g_kept->first;
  const std::size_t at = text.find("): ");
  if (at != std::string::npos) text = text.substr(at + 3);
  text = text.substr(0, text.find('\n'));
  return text;
}

std::string vtkCause(unsigned long error_code) {
  const std::string cause = vtkFailure(error_code);
  return cause.empty() ? vtkError() : cause;
}

std::string cannotWrite(const std::string& path, unsigned long error_code) {
  return failed("cannot write", path, error_code);
}

std::string cannotRead(const std::string& path, unsigned long error_code) {
  return failed("cannot read", path, error_code);
}

}  // namespace fesph
