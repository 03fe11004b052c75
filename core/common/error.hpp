// SPDX-License-Identifier: MIT
// Error types. InputError points at the file, line and column of bad input (exit code 2);
// RunError reports a failed run with where it stopped (exit code 1).
#pragma once

#include <cstdio>
#include <stdexcept>
#include <string>

namespace fesph {

/// Bad input: a scene, material library or mesh that cannot be used. Carries its location.
class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, int column, const std::string& what)
      : std::runtime_error(format(file, line, column, what)),
        file_(std::move(file)), message_(what), line_(line), column_(column) {}
  const std::string& file() const { return file_; }
  /// What was wrong, without the location.
  const std::string& message() const { return message_; }
  int line() const { return line_; }
  int column() const { return column_; }

 private:
  static std::string format(const std::string& f, int line, int col, const std::string& w) {
    std::string loc = f.empty() ? std::string("<input>") : f;
    if (line > 0) loc += ":" + std::to_string(line);
    if (line > 0 && col > 0) loc += ":" + std::to_string(col);
    return loc + ": error: " + w;
  }
  std::string file_, message_;
  int line_ = 0, column_ = 0;
};

/// A run that cannot continue (non-finite state, inverted element, time step collapse).
class RunError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A time for a message, "1.23456789e-05 s": std::to_string would print 0.000012.
inline std::string seconds(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g s", t);
  return buf;
}

}  // namespace fesph
