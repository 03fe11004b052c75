// SPDX-License-Identifier: MIT
// VTK's failures in fesph's own words. Every reader and writer is checked, and its failure
// thrown as a RunError naming the file and the cause: the error code's (vtkFailure), else the
// message VTK gave. Under quietVtk VTK's own messages (coloured, time-stamped, several lines
// for one full disk) are kept for that, not printed.
#pragma once

#include <string>

namespace fesph {

/// The cause of a VTK reader's or writer's error code (vtkErrorCode, or the errno it passes
/// on), e.g. "the disk is full"; empty for no error.
std::string vtkFailure(unsigned long error_code);

/// VTK's messages from now on are kept, not printed (for the process).
void quietVtk();
/// Forget the VTK error kept so far: call before the operation to check.
void clearVtkError();
/// The first VTK error since clearVtkError(), without VTK's source line and object address;
/// empty if none, or without quietVtk.
std::string vtkError();

/// What went wrong: the error code's cause, else the VTK error kept; empty if neither.
std::string vtkCause(unsigned long error_code);

/// "cannot write PATH: CAUSE" (or "cannot read ..."), CAUSE as vtkCause.
std::string cannotWrite(const std::string& path, unsigned long error_code);
std::string cannotRead(const std::string& path, unsigned long error_code);

}  // namespace fesph
