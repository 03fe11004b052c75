// SPDX-License-Identifier: MIT
// The fesph sub-commands. Each returns the process exit code: 0 ok, 1 run failure, 2 bad input.
#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace fesph {

struct RunInfo;

struct RunOptions {
  std::string scene;
  std::string restart;                ///< checkpoint to continue from (instead of a scene)
  std::string out;                    ///< overrides [output].folder
  double end_time = 0;                ///< overrides [simulation].end_time when > 0
  int threads = 0;                    ///< OpenMP threads; 0: the default
  std::vector<std::string> overrides; ///< --set key=value
  std::string materials;              ///< material library path; empty: found from the scene
  bool quiet = false;                 ///< no progress display
  bool no_images = false;             ///< skip the images at the end
};

int runCommand(const RunOptions& opt);

/// Sets the OpenMP threads of the runs to come (`threads` > 0; 0 keeps the default: all cores),
/// with a warning on stderr when they are more than the cores the process may use.
void useThreads(int threads);

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
/// The line (indented, with its newline) saying that `asked` is no output time of the run and
/// `found`, the nearest, was `done` ("drawn", "compared") instead; empty when `asked` < 0 (the
/// last output asked for) or is `found`.
std::string nearestOutputNote(double asked, double found, const std::string& done);
/// Whether `name` is one of the files renderRun writes (which a new run into the folder removes).
bool isRenderedFile(const std::string& name);

struct ReportOptions {
  std::vector<std::string> run_dirs;  ///< run folders; the first one's scene gives the reference
  std::string out;                    ///< report folder; empty: <first run's parent>/report
};

int reportCommand(const ReportOptions& opt);

struct CompareCommandOptions {
  std::string run_dir;
  std::string plate = "1";    ///< 1-based plate number (bodies that are not projectiles) or name
  std::string image;          ///< photograph of the tested plate
  double mm_per_px = 0;       ///< the photograph's scale
  std::string center;         ///< "X,Y": pixel of the plate's centre; empty: align the holes
  double threshold = -1;      ///< brightness in (0, 1); < 0: Otsu's
  std::string holes = "dark"; ///< dark or bright holes
  std::string face = "front"; ///< the face photographed: front or rear
  double time = -1;           ///< output time of the run; < 0: the last
  std::string out;            ///< folder; empty: RUN_DIR/compare
};

int compareCommand(const CompareCommandOptions& opt);
/// The options of `compare` after RUN_DIR (shared by `fesph compare` and the shell).
void addCompareOptions(CLI::App& cmd, CompareCommandOptions& o);

/// Body index of plate `which` of a run: a 1-based number among the bodies that are not
/// projectiles, or a body name. Throws std::invalid_argument listing the plates.
int plateBody(const RunInfo& info, const std::string& which);

}  // namespace fesph
