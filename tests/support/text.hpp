// SPDX-License-Identifier: MIT
// Whole files and counts of a piece of text, for tests that read what a run or a command wrote.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fesph::testing {

/// The whole file, byte for byte; empty when it cannot be read.
inline std::string slurp(const std::filesystem::path& p) {
  std::stringstream s;
  s << std::ifstream(p, std::ios::binary).rdbuf();
  return s.str();
}

/// How many times `what` occurs in `text` (overlapping occurrences too).
inline std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace fesph::testing
