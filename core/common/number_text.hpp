// SPDX-License-Identifier: MIT
// Numbers as text that reads back to the same double.
#pragma once

#include <charconv>
#include <string>

namespace fesph {

/// The shortest text that reads back as the same double (std::to_chars): 1e-06 and
/// 1.0000001e-06 stay apart, and a number typed as 2.5e-05 is written so.
inline std::string shortestText(double x) {
  char buf[32];
  const std::to_chars_result r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

}  // namespace fesph
