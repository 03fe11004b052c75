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
  bool no_images = false;             ///< skip the images at the end
};

int runCommand(const RunOptions& opt);

struct RenderOptions {
  std::string run_dir;
  std::vector<double> times;  ///< output times to draw; empty: the last one
  std::string field = "damage";
  std::string size = "1600x1200";  ///< WxH in pixels
  std::string out;                 ///< image folder; empty: RUN_DIR/images
};

int renderCommand(const RenderOptions& opt);

/// Draw the images of one run folder (plates front/rear with hole outlines, section,
/// velocity plot, hole metrics CSV/JSON) at `time` (< 0: the last output) into `out_dir`.
/// Throws RunError.
void renderRun(const std::string& run_dir, double time, const std::string& field, int width,
               int height, const std::string& out_dir);

}  // namespace fesph
