// SPDX-License-Identifier: MIT
// A fresh, empty folder under the system temp directory for one test, removed at scope exit
// (kept when FESPH_KEEP_TEST_OUTPUT is set, to look at what a test wrote).
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>
#include <unistd.h>

namespace fesph::testing {

struct TempFolder {
  std::filesystem::path path;
  explicit TempFolder(const std::string& name)
      : path(std::filesystem::temp_directory_path() /
             ("fesph_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempFolder() {
    if (!std::getenv("FESPH_KEEP_TEST_OUTPUT")) std::filesystem::remove_all(path);
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
};

}  // namespace fesph::testing
