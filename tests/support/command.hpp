// SPDX-License-Identifier: MIT
// A command line run through /bin/sh, with what it printed and its exit code: the tests that
// drive the fesph binary.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace fesph::testing {

struct CommandResult {
  int code = 0;
  std::string out;  ///< what the command printed (its stderr too where it says 2>&1)
};

/// Runs `command` as given and reads its standard output to the end.
inline CommandResult runCommand(const std::string& command) {
  CommandResult r;
  FILE* p = popen(command.c_str(), "r");
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p)) r.out += buf;
  r.code = WEXITSTATUS(pclose(p));
  return r;
}

}  // namespace fesph::testing
