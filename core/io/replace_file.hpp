// SPDX-License-Identifier: MIT
// Files replaced whole: written under a temporary name beside the target and renamed over it,
// so that a reader (or a run killed mid-write) sees the old file or the new one, never half.
#pragma once

#include <string>

namespace fesph {

/// The temporary a writer fills before renameInto: the target's name + ".tmp", in the same
/// folder, so that the rename never crosses a file system and stays atomic.
std::string temporaryFor(const std::string& target);

/// Rename `tmp` over `target`. On failure `tmp` is removed and RunError names both.
void renameInto(const std::string& tmp, const std::string& target);

/// Replace `target` with `text` through its temporary. Throws RunError (the old file stays).
void replaceFile(const std::string& target, const std::string& text);

}  // namespace fesph
