// SPDX-License-Identifier: MIT
// The fesph sub-commands. Each returns the process exit code: 0 ok, 1 run failure, 2 bad input.
#pragma once

#include <string>
#include <vector>

namespace fesph {

struct RunOptions {
  std::string scene;
  std::string out;                    ///< overrides [output].folder
  double end_time = 0;                ///< overrides [simulation].end_time when > 0
  int threads = 0;                    ///< OpenMP threads; 0: the default
  std::vector<std::string> overrides; ///< --set key=value
  std::string materials;              ///< material library path; empty: found from the scene
  bool quiet = false;                 ///< no progress display
};

int runCommand(const RunOptions& opt);

}  // namespace fesph
