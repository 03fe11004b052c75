// SPDX-License-Identifier: MIT
// A whole file read into memory, or why it could not be: the readers of scenes, material
// libraries and series indexes say the same things of a path that is missing, a folder, or
// unreadable, each with its own error type.
#pragma once

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

namespace fesph {

/// The bytes of the file at `path` into `text`; false, with `why` saying why not ("a folder,
/// not a file", or the system's reason: "No such file or directory"), when it cannot be
/// read whole.
inline bool readWholeFile(const std::string& path, std::string& text, std::string& why) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    why = "a folder, not a file";
    return false;
  }
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) {
    why = std::strerror(errno);
    return false;
  }
  text.clear();
  char buffer[1 << 16];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, f)) > 0;) text.append(buffer, n);
  const bool failed = std::ferror(f) != 0;
  const int error = errno;
  std::fclose(f);
  if (failed) why = std::strerror(error);
  return !failed;
}

}  // namespace fesph
