// SPDX-License-Identifier: MIT
#include "core/io/replace_file.hpp"

#include "core/common/error.hpp"

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace fesph {

std::string temporaryFor(const std::string& target) { return target + ".tmp"; }

void renameInto(const std::string& tmp, const std::string& target) {
  if (std::rename(tmp.c_str(), target.c_str()) != 0) {
    const std::error_code ec(errno, std::generic_category());
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw RunError("cannot rename " + tmp + " to " + target + ": " + ec.message());
  }
}

void replaceFile(const std::string& target, const std::string& text) {
  const std::string tmp = temporaryFor(target);
  {
    std::ofstream out(tmp, std::ios::trunc);
    if (!out.is_open()) throw RunError("cannot write " + tmp);
    out << text;
    out.close();
    if (!out) {  // the half-written temporary goes; the target stays as it was
      std::error_code ignored;
      std::filesystem::remove(tmp, ignored);
      throw RunError("cannot write " + tmp);
    }
  }
  renameInto(tmp, target);
}

}  // namespace fesph
