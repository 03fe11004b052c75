// SPDX-License-Identifier: MIT
// `fesph run`, `fesph render` and `fesph compare` through the binary: a scene named from its
// own folder, command-line values that say what was expected when they are wrong, an output
// folder that cannot be made, a restart that refuses changes it could not make, a failed run's
// last state (also at its first step, and at once after a restart), the history's rows and the
// summary's counts.
#include "tests/support/command.hpp"
#include "tests/support/temp_folder.hpp"
#include "tests/support/text.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

using fesph::testing::occurrences;
using fesph::testing::slurp;
using fesph::testing::TempFolder;
namespace fs = std::filesystem;

namespace {

using Result = fesph::testing::CommandResult;

// fesph with `args`, run in `dir`; its stdout and stderr.
Result command(const std::string& args, const fs::path& dir) {
  return fesph::testing::runCommand("cd '" + dir.string() + "' && " + std::string(FESPH_BINARY) +
                                    " " + args + " 2>&1");
}

bool has(const std::string& text, const std::string& what) {
  return text.find(what) != std::string::npos;
}

/// fesph run of the test scene (tests/app/shell_scene.toml) with `options`, into `dir`/run,
/// quietly and without images.
Result runTestScene(const std::string& options, const fs::path& dir) {
  return command("run " + std::string(FESPH_TEST_APP_DIR) + "/shell_scene.toml " + options +
                     " --out run --quiet --no-images",
                 dir);
}

/// The `step` column of history.csv's rows, in order.
std::vector<long> historySteps(const fs::path& csv) {
  std::istringstream in(slurp(csv));
  std::string line;
  std::getline(in, line);  // header: time,step,...
  std::vector<long> steps;
  while (std::getline(in, line)) steps.push_back(std::stol(line.substr(line.find(',') + 1)));
  return steps;
}

/// A photograph of a plate with one hole: a dark disc of radius 20 px in a 100 px square PGM.
void writeDiscPhoto(const fs::path& path) {
  std::ofstream photo(path, std::ios::binary);
  photo << "P5\n100 100\n255\n";
  for (int j = 0; j < 100; ++j)
    for (int i = 0; i < 100; ++i)
      photo.put(static_cast<char>(std::hypot(i - 49.5, j - 49.5) < 20 ? 30 : 200));
}

/// `steps = N` of a run's summary.toml.
long summarySteps(const fs::path& summary) {
  std::smatch m;
  const std::string text = slurp(summary);
  REQUIRE(std::regex_search(text, m, std::regex("\nsteps = ([0-9]+)\n")));
  return std::stol(m[1]);
}

/// fesph run of the test scene with `--end-time ARGS` into `dir`/run, stopped by SIGINT once
/// its history has 4 lines; its exit code and its log (stdout and stderr).
std::pair<int, std::string> interruptedRun(const fs::path& dir, const std::string& args) {
  const fs::path run = dir / "run";
  const pid_t pid = fesph::testing::startAndWait(
      std::string(FESPH_BINARY) + " run " + FESPH_TEST_APP_DIR + "/shell_scene.toml --end-time " +
          args + " --out " + run.string() + " > " + (dir / "log").string() + " 2>&1",
      [&] { return occurrences(slurp(run / "history.csv"), "\n") >= 4; });
  REQUIRE(pid > 0);
  const int code = fesph::testing::signalAndWait(pid, SIGINT);
  return {code, slurp(dir / "log")};
}

}  // namespace

TEST_CASE("fesph run, render and compare: a scene named from its own folder, and times given wrong",
          "[app]") {
  const TempFolder dir("command_line");
  fs::copy_file(std::string(FESPH_TEST_APP_DIR) + "/shell_scene.toml", dir.path / "scene.toml");

  // "scene.toml" has an empty parent path: the material library search aborted on it.
  const Result run = command("run scene.toml --end-time 1e-6 --out run --quiet --no-images", dir.path);
  INFO(run.out);
  REQUIRE(run.code == 0);
  REQUIRE(fs::exists(dir.path / "run" / "elements.pvd"));

  // CLI11's own check printed the largest double, 309 digits, as the end of the range.
  for (const char* value : {"abc", "1e-6x"}) {
    const Result r = command(std::string("run scene.toml --end-time ") + value, dir.path);
    INFO(r.out);
    CHECK(r.code == 2);
    CHECK(has(r.out, std::string("--end-time: expected a number, got '") + value + "'"));
    CHECK(!has(r.out, "179769"));
  }
  for (const char* value : {"-1", "0", "inf", "nan"}) {
    const Result r = command(std::string("run scene.toml --end-time ") + value, dir.path);
    INFO(r.out);
    CHECK(r.code == 2);
    CHECK(has(r.out, std::string("--end-time: expected a number > 0, got ") + value));
  }
  // CLI11's Range said "Value abc not in range 1 to 1024" of a word.
  for (const char* value : {"abc", "0", "2.5", "1025"}) {
    const Result r = command(std::string("run scene.toml --threads ") + value, dir.path);
    INFO(r.out);
    CHECK(r.code == 2);
    CHECK(has(r.out, std::string("--threads: expected a whole number from 1 to 1024, got '") +
                         value + "'"));
  }

  // A time between outputs or past the end (typed in us, not s) is drawn at the nearest
  // output, and says so; a negative one is an error (it used to draw the last output).
  const Result past = command("render run --time 5 --size 64x64", dir.path);
  INFO(past.out);
  CHECK(past.code == 0);
  CHECK(has(past.out, "no output at t = 5 s: drawn at the nearest, t = 1e-06 s"));
  const Result exact = command("render run --time 1e-6 --size 64x64", dir.path);
  INFO(exact.out);
  CHECK(exact.code == 0);
  CHECK(!has(exact.out, "no output at"));
  const Result negative = command("render run --time -1", dir.path);
  INFO(negative.out);
  CHECK(negative.code == 2);
  CHECK(has(negative.out, "--time: expected a number >= 0, got -1"));

  // fesph compare takes the nearest output too: it said only "at t = 1.000 us" in its heading.
  writeDiscPhoto(dir.path / "photo.pgm");
  const std::string compare = "compare run --image photo.pgm --mm-per-px 0.1 ";
  const Result late = command(compare + "--time 5 --center 50,50", dir.path);
  INFO(late.out);
  CHECK(late.code == 0);
  CHECK(has(late.out, "no output at t = 5 s: compared at the nearest, t = 1e-06 s"));
  const Result exact_compare = command(compare + "--time 1e-6 --center 50,50", dir.path);
  INFO(exact_compare.out);
  CHECK(exact_compare.code == 0);
  CHECK(!has(exact_compare.out, "no output at"));
  // A comparison that cannot be made (no hole at the start to align on) says of which time.
  const Result start = command(compare + "--time 0", dir.path);
  INFO(start.out);
  CHECK(start.code == 2);
  CHECK(has(start.out, "fesph compare: plate 'plate' at t = 0.000 us against photo.pgm"));
  CHECK(has(start.out, "error: the simulated plate has no through-hole"));
}

TEST_CASE("fesph render: a field or size given wrong, times too close for six digits, and "
          "fesph run's --end-time and --threads as given",
          "[app]") {
  const TempFolder dir("render_command_line");
  const Result run = runTestScene("--end-time 1e-6", dir.path);
  INFO(run.out);
  REQUIRE(run.code == 0);

  // Bad input, exit code 2, as for the run's options: the field exited with 1 (a failed run).
  const Result field = command("render run --field nosuch --size 64x64", dir.path);
  INFO(field.out);
  CHECK(field.code == 2);
  CHECK(has(field.out, "error: --field: no scalar cell field \"nosuch\""));
  CHECK(has(field.out, "plastic_strain"));
  // Anything after WxH was ignored: 100x100x drew 100 x 100 images.
  for (const char* size :
       {"100x100x", "100x100 ", "64x64x64", "x64", "100X100", "63x64", "64x63", "8193x64", "64x8193"}) {
    const Result r = command(std::string("render run --size '") + size + "'", dir.path);
    INFO(r.out);
    CHECK(r.code == 2);
    CHECK(has(r.out, std::string("--size must be WxH with 64..8192 pixels each, got '") + size));
  }

  // A folder that holds no run is bad input too, said before anything is drawn.
  fs::create_directory(dir.path / "empty");
  const Result empty = command("render empty --size 64x64", dir.path);
  INFO(empty.out);
  CHECK(empty.code == 2);
  CHECK(has(empty.out, "empty is not a run folder (no elements.pvd)"));

  // Two times that print alike to six digits went into one folder (the second drawing over
  // the first), and the message said "no output at t = 1e-06 s: drawn at ... t = 1e-06 s".
  const Result close = command("render run --time 1e-6 --time 1.0000001e-6 --size 64x64", dir.path);
  INFO(close.out);
  CHECK(close.code == 0);
  CHECK(fs::exists(dir.path / "run" / "images" / "t_1e-06" / "plate_front.png"));
  CHECK(fs::exists(dir.path / "run" / "images" / "t_1.0000001e-06" / "plate_front.png"));
  CHECK(occurrences(close.out, "no output at") == 1);
  CHECK(has(close.out, "no output at t = 1.0000001e-06 s: drawn at the nearest, t = 1e-06 s"));

  // --end-time to every digit given (it goes to the scene as a --set of simulation.end_time).
  const Result precise = command("run " + std::string(FESPH_TEST_APP_DIR) +
                                     "/shell_scene.toml --end-time 3.00000001e-7 --out precise "
                                     "--threads 2 --quiet --no-images",
                                 dir.path);
  INFO(precise.out);
  REQUIRE(precise.code == 0);
  CHECK(has(slurp(dir.path / "precise" / "summary.toml"), "\nend_time = 3.00000001e-07\n"));
  // 2, not ctest's OMP_NUM_THREADS=1: --threads is what sets it
  CHECK(has(slurp(dir.path / "precise" / "summary.toml"), "\nthreads = 2\n"));
  CHECK(has(slurp(dir.path / "precise" / "summary.toml"), "\nstatus = \"complete\"\n"));
  // More threads than the cores the run may use (taskset: one) take turns: a warning, the run
  // as it would be (the results the same bits for any thread count: test_determinism.cpp).
  const Result turns = fesph::testing::runCommand(
      "cd '" + dir.path.string() + "' && taskset -c 0 " + FESPH_BINARY + " run " +
      FESPH_TEST_APP_DIR + "/shell_scene.toml --end-time 1e-7 --out turns --threads 2 --quiet "
      "--no-images 2>&1");
  INFO(turns.out);
  CHECK(turns.code == 0);
  CHECK(has(turns.out, "warning: --threads 2 is more than the 1 core this run may use"));
  CHECK(!has(precise.out, "warning: --threads"));
}

TEST_CASE("a half model's energies are said to be the modelled part's, in the summary and the "
          "shell's probe",
          "[app]") {
  // Its energies, momentum and masses are the half's (its velocities the full bodies'): the
  // summary gave them as they were, beside the full projectile's velocity.
  const TempFolder dir("half_energies");
  const std::string note = "(the modelled part's, without its mirror images)";
  const Result full = runTestScene("--end-time 1e-7", dir.path);
  INFO(full.out);
  REQUIRE(full.code == 0);
  CHECK(!has(full.out, note));
  const std::string half = " --set simulation.symmetry='\"half\"'";
  const std::string scene = std::string(FESPH_TEST_APP_DIR) + "/shell_scene.toml";
  const Result run =
      command("run " + scene + " --end-time 1e-7 --out half --quiet --no-images" + half, dir.path);
  INFO(run.out);
  REQUIRE(run.code == 0);
  CHECK(has(run.out, "eroded 0  " + note));
  std::ofstream(dir.path / "steps.txt") << "step 2\nprobe\n";
  const Result probe = command("shell " + scene + " --out probe" + half + " < steps.txt", dir.path);
  INFO(probe.out);
  CHECK(probe.code == 0);
  CHECK(has(probe.out, "balance error 0 %\n                " + note));
}

TEST_CASE("a run with two projectiles measures each one at the plates", "[app]") {
  // Only the scene's first projectile was measured: a second one (a follower 10 mm behind, as
  // the core behind a jacket or a second fragment) had no v_k in the summary,
  // residual_velocities.csv, the shell's probe or the report.
  const TempFolder dir("two_projectiles");
  const std::string follower = R"(
[[bodies]]
name = "follower"
material = "steel_1020"
projectile = true
velocity = [0.0, 0.0, -600.0]
position = [0.0, 0.0, 16.3e-3]
[bodies.shape]
type = "projectile"
nose = "flat"
diameter = 6e-3
length = 6e-3
mesh_size = 1.5e-3
)";
  const std::string one = slurp(std::string(FESPH_TEST_APP_DIR) + "/shell_scene.toml");
  std::ofstream(dir.path / "two.toml") << one << follower;
  const Result single = runTestScene("--end-time 1e-7", dir.path);
  INFO(single.out);
  REQUIRE(single.code == 0);
  CHECK(occurrences(single.out, "  after plate 1 ") == 1);
  // By 1 us the first has hit the plate (its nose 0.3 mm off it at 600 m/s), the follower not.
  const Result run = command("run two.toml --end-time 1e-6 --out two --quiet --no-images "
                             "--set output.checkpoint_interval=5e-7", dir.path);
  INFO(run.out);
  REQUIRE(run.code == 0);
  // each projectile's plate lines under its own name
  const std::size_t second = run.out.find("projectile 'follower'");
  REQUIRE(second != std::string::npos);
  const std::size_t hit = run.out.find("  after plate 1    not measured (hit, not through yet)\n");
  CHECK(hit > run.out.find("projectile 'projectile'"));
  CHECK(hit < second);
  const std::size_t unreached = run.out.find("  after plate 1    not measured (not reached)\n");
  REQUIRE(unreached != std::string::npos);
  CHECK(unreached > second);
  const std::string csv = slurp(dir.path / "two" / "residual_velocities.csv");
  // Continued from its checkpoint at 0.5 us into another folder, it goes on tracking both.
  const Result resumed = command("run --restart $(ls two/checkpoint_*.h5 | head -1) --out split "
                                 "--quiet --no-images", dir.path);
  INFO(resumed.out);
  CHECK(resumed.code == 0);
  CHECK(slurp(dir.path / "split" / "residual_velocities.csv") == csv);
  CHECK(csv.rfind("plate,name,", 0) == 0);
  CHECK(has(csv, ",through_mass_fraction,projectile\n1,plate,"));
  // a row each, ending with the projectile's name (the test scene calls the first "projectile")
  CHECK(has(csv, ",projectile\n1,plate,"));
  CHECK(csv.substr(csv.size() - 10) == ",follower\n");
  CHECK(occurrences(csv, "\n1,plate,") == 2);
  // The shell's probe gives each one's distance to its next measuring plane.
  std::ofstream(dir.path / "probe.txt") << "step 2\nprobe\n";
  const Result probe = command("shell two.toml --out probe < probe.txt", dir.path);
  INFO(probe.out);
  CHECK(probe.code == 0);
  CHECK(occurrences(probe.out, "projectile '") == 2);
  CHECK(occurrences(probe.out, "piece's lead") == 2);
  CHECK(probe.out.find("piece's lead", probe.out.find("projectile 'follower'")) !=
        std::string::npos);
  // The report: the table compares the first; the next section has a row for each.
  const Result report = command("report two --out report", dir.path);
  INFO(report.out);
  REQUIRE(report.code == 0);
  const std::string md = slurp(dir.path / "report" / "report.md");
  CHECK(has(md, "\nerosion 0.6 (default, two) has 2 projectiles; the table gives the scene's "
                "first, 'projectile'; the next section gives each one.\n"));
  CHECK(has(md, "\n| v1 | erosion 0.6 (default, two) 'projectile' | "));
  CHECK(has(md, "\n| v1 | erosion 0.6 (default, two) 'follower' | "));
  const std::string through = slurp(dir.path / "report" / "through.csv");
  CHECK(has(through, ",through_mass_fraction,projectile\n1,"));
  CHECK(occurrences(through, "\n1,") == 2);
  CHECK(has(through, ",follower\n"));
}

TEST_CASE("a projectile shot away from the plates is warned of, and not said to have cleared them",
          "[app]") {
  // A velocity's sign typed wrong: the run went on silently, and its summary said the
  // projectile "has cleared every target" it never reached.
  const TempFolder dir("shot_away");
  const Result towards = runTestScene("--end-time 1e-7", dir.path);
  INFO(towards.out);
  REQUIRE(towards.code == 0);
  CHECK(!has(towards.out, "warning"));
  CHECK(!has(towards.out, "it has reached none"));
  const Result away = runTestScene("--end-time 1e-7 --set bodies.0.velocity=[0,0,600]", dir.path);
  INFO(away.out);
  REQUIRE(away.code == 0);
  CHECK(has(away.out, "/shell_scene.toml:17: warning: projectile 'projectile' moves away from "
                      "every plate, at (0, 0, 600) m/s: no plate will be crossed"));
  CHECK(has(away.out, "no target ahead of it, and it has reached none)"));
  CHECK(!has(away.out, "it has cleared every target"));
  // Shot past the plate's edge (the plate 30 mm aside): it reaches the plate's plane and
  // clears it in 20 us at 600 m/s, untouched.
  const Result past = runTestScene("--end-time 2e-5 --set bodies.1.position=[30e-3,0,0]", dir.path);
  INFO(past.out);
  REQUIRE(past.code == 0);
  CHECK(!has(past.out, "warning"));
  CHECK(has(past.out, "residual velocity 600.0 m/s (largest intact piece, 100.0 % of the initial "
                      "mass; it has cleared every target)"));
}

TEST_CASE("a series file cut short or not VTK is named with VTK's cause, in one line", "[app]") {
  // VTK's own messages (coloured, time-stamped, a line from each pipeline stage) are kept for
  // fesph's message instead; the file cut short was read as a series without a "body" array.
  const TempFolder dir("cut_short");
  REQUIRE(runTestScene("--end-time 1e-6", dir.path).code == 0);
  const fs::path last = dir.path / "run" / "elements_000001.vtu";
  const std::string whole = slurp(last);
  REQUIRE(whole.size() > 20000);
  std::ofstream(last, std::ios::trunc) << whole.substr(0, whole.size() / 2);
  const Result cut = command("render run --size 64x64", dir.path);
  INFO(cut.out);
  CHECK(cut.code == 1);
  CHECK(has(cut.out, "error: cannot read run/elements_000001.vtu: Cannot read "));
  CHECK(!has(cut.out, "\x1b["));  // no terminal colours
  CHECK(!has(cut.out, "ERR|"));
  CHECK(occurrences(cut.out, "\n") == 1);
  std::ofstream(last, std::ios::trunc) << "not xml\n";
  const Result garbage = command("render run --size 64x64", dir.path);
  INFO(garbage.out);
  CHECK(garbage.code == 1);
  CHECK(has(garbage.out, "error: cannot read run/elements_000001.vtu: Error parsing XML"));
}

TEST_CASE("fesph run: an output folder that cannot be made is said before the meshing", "[app]") {
  const TempFolder dir("output_folder");
  fs::copy_file(std::string(FESPH_TEST_APP_DIR) + "/shell_scene.toml", dir.path / "scene.toml");
  std::ofstream(dir.path / "taken") << "a file, not a folder\n";
  const Result file = command("run scene.toml --end-time 1e-6 --out taken --no-images", dir.path);
  INFO(file.out);
  CHECK(file.code == 2);
  CHECK(has(file.out, "cannot create output folder taken: Not a directory"));
  CHECK(!has(file.out, "Meshing"));

  // A folder made for a run whose model cannot be built (the projectile placed 1 mm into the
  // plate) is taken away again; one that was there is left.
  const std::string overlap = "run scene.toml --set 'bodies.0.position=[0,0,-1e-3]' --no-images ";
  const Result fresh = command(overlap + "--out new", dir.path);
  INFO(fresh.out);
  CHECK(fresh.code == 2);
  CHECK(has(fresh.out, "overlap at the start"));
  CHECK(!fs::exists(dir.path / "new"));
  fs::create_directory(dir.path / "old");
  CHECK(command(overlap + "--out old", dir.path).code == 2);
  CHECK(fs::is_directory(dir.path / "old"));
}

TEST_CASE("fesph run --restart refuses changes a checkpoint cannot take", "[app]") {
  const TempFolder dir("restart_changes");
  const std::string scene = std::string(FESPH_TEST_APP_DIR) + "/shell_scene.toml";
  const std::string own = " --set 'bodies.0.velocity=[0,0,-500]'";  // the run's own override
  const Result first = command("run " + scene + " --end-time 2e-6 --out run --quiet --no-images " +
                                   "--set output.checkpoint_interval=1e-6" + own,
                               dir.path);
  INFO(first.out);
  REQUIRE(first.code == 0);
  fs::path saved;  // the newest (checkpoint_STEP.h5, zero-padded): an older one is refused
  for (const auto& f : fs::directory_iterator(dir.path / "run"))
    if (f.path().filename().string().rfind("checkpoint_", 0) == 0 && f.path() > saved)
      saved = f.path();
  REQUIRE(!saved.empty());

  // The meshes, materials and symmetry are the checkpoint's: such a change was read and then
  // silently never used.
  for (const char* change : {"bodies.0.velocity=[0,0,-10]", "materials.A36.density=1000",
                             "bodies.plate.shape.thickness=9e-3", "resolution=\"quick\"",
                             "simulation.symmetry=\"half\""}) {
    const Result r =
        command("run --restart " + saved.string() + " --end-time 3e-6 --quiet --no-images --set '" +
                    change + "'",
                dir.path);
    INFO(r.out);
    CHECK(r.code == 2);
    CHECK(has(r.out, "cannot change"));
  }
  // An end time before the checkpoint's: it said "Running to t = 1e-06 s", ran nothing and
  // wrote a complete summary at 2 us.
  const std::string summary_before = slurp(dir.path / "run" / "summary.toml");
  const Result early =
      command("run --restart " + saved.string() + " --end-time 1e-6 --quiet --no-images", dir.path);
  INFO(early.out);
  CHECK(early.code == 2);
  CHECK(has(early.out, "the end time 1e-06 s lies before the checkpoint's t = 2e-06 s"));
  CHECK(slurp(dir.path / "run" / "summary.toml") == summary_before);
  // The controls can, and the run's own overrides given again change nothing.
  const Result on = command("run --restart " + saved.string() +
                                " --end-time 3e-6 --quiet --no-images --set simulation.courant=0.4" +
                                own,
                            dir.path);
  INFO(on.out);
  CHECK(on.code == 0);

  // Failing at once, at the checkpoint's time (a time step floor of 1 s), in a fresh folder:
  // the state it stopped in, the checkpoint's, is that folder's one output.
  const Result failed = command("run --restart " + saved.string() +
                                    " --out fresh --end-time 3e-6 --quiet --no-images --set simulation.dt_min=1",
                                dir.path);
  INFO(failed.out);
  CHECK(failed.code == 1);
  const std::string pvd = slurp(dir.path / "fresh" / "elements.pvd");
  CHECK(occurrences(pvd, "<DataSet") == 1);
  CHECK(has(pvd, "timestep=\"2e-06\""));
}

TEST_CASE("a run into another run's folder replaces it whole, and that run's checkpoints cannot "
          "continue there",
          "[app]") {
  const TempFolder dir("run_over_run");
  const Result first = runTestScene("--end-time 3e-6 --set output.checkpoint_interval=1e-6 "
                                    "--set output.checkpoints_kept=5",
                                    dir.path);
  INFO(first.out);
  REQUIRE(first.code == 0);
  const auto checkpoints = [&] {
    std::vector<fs::path> found;
    for (const auto& f : fs::directory_iterator(dir.path / "run"))
      if (f.path().filename().string().rfind("checkpoint_", 0) == 0) found.push_back(f.path());
    std::sort(found.begin(), found.end());
    return found;
  };
  REQUIRE(checkpoints().size() == 3);
  const fs::path earlier = dir.path / "earlier.h5";  // the first run's, at 2 us
  fs::copy_file(checkpoints()[1], earlier);
  const Result drawn = command("render run --size 64x64", dir.path);
  INFO(drawn.out);
  REQUIRE(drawn.code == 0);
  REQUIRE(fs::exists(dir.path / "run" / "images" / "plate_front.png"));
  REQUIRE(command("render run --size 64x64 --time 1e-6", dir.path).code == 0);
  REQUIRE(fs::exists(dir.path / "run" / "images" / "t_1e-06" / "plate_rear.png"));
  std::ofstream(dir.path / "run" / "images" / "notes.txt") << "the user's own file\n";

  // Another run into the same folder, slower and without checkpoints or images. The first
  // run's checkpoints stayed: its later ones then went on with the second run's history cut
  // back under them, and its images showed the other run.
  const Result second =
      runTestScene("--end-time 3e-6 --set 'bodies.0.velocity=[0,0,-300]'", dir.path);
  INFO(second.out);
  REQUIRE(second.code == 0);
  CHECK(checkpoints().empty());
  CHECK(!fs::exists(dir.path / "run" / "images" / "plate_front.png"));
  CHECK(!fs::exists(dir.path / "run" / "images" / "holes.csv"));
  CHECK(!fs::exists(dir.path / "run" / "images" / "t_1e-06"));
  CHECK(fs::exists(dir.path / "run" / "images" / "notes.txt"));  // not fesph's: kept
  CHECK(has(second.out, "the run there before is replaced: its series and histories, 3 checkpoints "
                        "and 14 files of images/"));

  // A checkpoint of the first run put back into the folder is refused there, and the failed
  // restart leaves the second run's files as they were (it rewrote scene.toml first).
  fs::copy_file(earlier, dir.path / "run" / earlier.filename());
  const std::string scene_before = slurp(dir.path / "run" / "scene.toml");
  const std::string history_before = slurp(dir.path / "run" / "history.csv");
  const std::string pvd_before = slurp(dir.path / "run" / "elements.pvd");
  const Result back = command("run --restart run/earlier.h5 --quiet --no-images", dir.path);
  INFO(back.out);
  CHECK(back.code == 2);
  CHECK(has(back.out, "holds another run than the one run/earlier.h5 was taken in"));
  CHECK(slurp(dir.path / "run" / "scene.toml") == scene_before);
  CHECK(slurp(dir.path / "run" / "history.csv") == history_before);
  CHECK(slurp(dir.path / "run" / "elements.pvd") == pvd_before);
  // Into a folder of its own it goes on. That folder's run before goes whole, as for a fresh
  // run: its checkpoints would outnumber this run's own when the oldest are pruned.
  fs::create_directory(dir.path / "elsewhere");
  fs::copy_file(earlier, dir.path / "elsewhere" / "checkpoint_000000999.h5");
  const Result elsewhere =
      command("run --restart run/earlier.h5 --out elsewhere --quiet --no-images", dir.path);
  INFO(elsewhere.out);
  CHECK(elsewhere.code == 0);
  CHECK(!fs::exists(dir.path / "elsewhere" / "checkpoint_000000999.h5"));
  CHECK(has(elsewhere.out, "the run there before is replaced: its 1 checkpoint\n"));

  // A third run: the images folder, fesph's files alone now, goes with them.
  fs::remove(dir.path / "run" / "images" / "notes.txt");
  REQUIRE(command("render run --size 64x64", dir.path).code == 0);
  const Result third =
      runTestScene("--end-time 2e-6 --set output.checkpoint_interval=1e-6", dir.path);
  INFO(third.out);
  REQUIRE(third.code == 0);
  CHECK(has(third.out, "the run there before is replaced: its series and histories and 7 files of "
                       "images/"));
  CHECK(!fs::exists(dir.path / "run" / "images"));
  // A restart of its own that fails on the run's files (run.h5 damaged) leaves the scene as
  // run as it was, where the scene with the restart's changes was written before the files
  // were opened.
  std::ofstream(dir.path / "run" / "run.h5", std::ios::trunc) << "not HDF5\n";
  const std::string third_scene = slurp(dir.path / "run" / "scene.toml");
  const Result damaged = command("run --restart " + checkpoints().back().string() +
                                     " --end-time 3e-6 --set simulation.courant=0.4 --quiet "
                                     "--no-images",
                                 dir.path);
  INFO(damaged.out);
  CHECK(damaged.code != 0);
  CHECK(has(damaged.out, "run.h5"));
  CHECK(slurp(dir.path / "run" / "scene.toml") == third_scene);
}

TEST_CASE("an interrupted run leaves its checkpoint and draws no images", "[app]") {
  // Ctrl-C asks to stop: the run ends its step and writes a checkpoint, and does not keep the
  // user waiting for the images of a run that has not ended (fesph render draws them).
  const TempFolder dir("interrupted");
  const fs::path run = dir.path / "run";
  const auto [code, log] = interruptedRun(dir.path, "1e-3 --quiet");
  INFO(log);
  CHECK(code == 1);
  CHECK(has(log, "checkpoint written to"));
  CHECK(has(slurp(run / "summary.toml"), "\nstatus = \"interrupted\"\n"));
  CHECK(!fs::exists(run / "images"));
  CHECK(!has(log, "warning"));  // 1 ms: some thousands of steps
}

TEST_CASE("an end time typed in seconds for microseconds is warned of at the first step", "[app]") {
  // 30 for 30e-6: billions of steps, and a log with no progress line before 10 % of them.
  const TempFolder dir("end_time_units");
  const std::string log = interruptedRun(dir.path, "30").second;
  INFO(log);
  std::smatch m;
  REQUIRE(std::regex_search(log, m, std::regex("warning: reaching t = 30 s takes about ([0-9.e+]+) "
                                               "steps at the first step's dt = ([0-9.e+-]+) s "
                                               "\\(scene times are in seconds")));
  CHECK(std::stod(m[1]) == Approx(30 / std::stod(m[2])).epsilon(0.01));
  CHECK(occurrences(log, "warning") == 1);  // once, not at every step
}

TEST_CASE("a run into a folder another run is writing in is refused, and that run goes on",
          "[app]") {
  // Two runs in one folder (a fesph run and a shell on the same scene, say) replaced each
  // other's series, histories and checkpoints as they went: files of neither run. The first
  // holds the folder's lock until it ends, however it ends.
  const TempFolder dir("locked");
  const fs::path run = dir.path / "run";
  const auto checkpoint = [&] {  // one of the first run's, once it wrote one
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(run, ec))  // not one being written (.tmp)
      if (entry.path().filename().string().rfind("checkpoint_", 0) == 0 &&
          entry.path().extension() == ".h5")
        return entry.path();
    return fs::path();
  };
  const pid_t pid = fesph::testing::startAndWait(
      std::string(FESPH_BINARY) + " run " + FESPH_TEST_APP_DIR +
          "/shell_scene.toml --end-time 1e-3 --set output.checkpoint_interval=0.5e-6 "
          "--set output.checkpoints_kept=100000 --out " +
          run.string() + " --quiet --no-images > " + (dir.path / "log").string() + " 2>&1",
      [&] { return !checkpoint().empty(); });
  REQUIRE(pid > 0);
  const Result second = runTestScene("--end-time 1e-6", dir.path);
  const Result restart =
      command("run --restart " + checkpoint().string() + " --quiet --no-images", dir.path);
  const std::string shell_script = (dir.path / "steps.txt").string();
  std::ofstream(shell_script) << "set simulation.end_time=1e-6\nrun\n";
  const Result shell = command("shell " + std::string(FESPH_TEST_APP_DIR) +
                                   "/shell_scene.toml --out run < " + shell_script,
                               dir.path);
  // the first run goes on, its series whole: the outputs after the refused runs' end time
  bool went_on = false;
  for (int k = 0; k < 400 && !went_on; ++k) {
    went_on = has(slurp(run / "elements.pvd"), "timestep=\"3e-06\"");
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const std::string pvd = slurp(run / "elements.pvd");
  // A report while it runs says so; after it was killed, that it ended without a word (its
  // summary still says "running", written at its last output).
  REQUIRE(command("report run --out report_running", dir.path).code == 0);
  // the lock goes with the process, however it ends
  REQUIRE(fesph::testing::signalAndWait(pid, SIGKILL) == -1);
  REQUIRE(command("report run --out report_killed", dir.path).code == 0);
  CHECK(has(slurp(dir.path / "report_running" / "report.md"), " | running |\n"));
  CHECK(has(slurp(dir.path / "report_killed" / "report.md"),
            " | ended abruptly (killed or crashed) |\n"));
  CHECK(has(slurp(run / "summary.toml"), "\nstatus = \"running\"\n"));
  INFO(second.out << "\n----\n" << shell.out << "\n----\n" << pvd);
  CHECK(went_on);
  for (const char* t : {"\"0\"", "\"1e-06\"", "\"2e-06\"", "\"3e-06\""})
    CHECK(occurrences(pvd, std::string("timestep=") + t) == 1);
  CHECK(second.code == 2);
  CHECK(has(second.out, "error: another fesph run is writing into run (process " +
                            std::to_string(pid) + "): two runs in one folder"));
  CHECK(shell.code == 1);
  CHECK(has(shell.out, "another fesph run is writing into run (process "));
  INFO(restart.out);
  CHECK(restart.code == 2);
  CHECK(has(restart.out, "another fesph run is writing into " + run.string() + " (process "));
  const Result after = runTestScene("--end-time 1e-6", dir.path);
  INFO(after.out);
  CHECK(after.code == 0);
}

TEST_CASE("a failed run keeps the state it stopped in as its last output", "[app]") {
  // A time step floor the run falls under at its 17th step: the error names the element whose
  // step collapsed, and the state is where to look at it.
  const TempFolder dir("failed_state");
  const Result r = runTestScene("--set simulation.dt_min=3e-8", dir.path);
  INFO(r.out);
  REQUIRE(r.code == 1);
  std::smatch stopped;
  REQUIRE(std::regex_search(r.out, stopped, std::regex("run stopped at t = ([0-9.e+-]+) s")));
  const std::string text = slurp(dir.path / "run" / "elements.pvd");
  std::vector<double> times;
  const std::regex timestep("timestep=\"([0-9.e+-]+)\"");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), timestep);
       it != std::sregex_iterator(); ++it)
    times.push_back(std::stod((*it)[1]));
  REQUIRE(times.size() == 2);  // the start, and the state it stopped in (before any output)
  CHECK(times[0] == 0);
  CHECK(times[1] == Approx(std::stod(stopped[1])).epsilon(1e-5));
  CHECK(fs::exists(dir.path / "run" / "elements_000001.vtu"));
  // the history's last row is the budget of the last step done, whatever history_every (5
  // here): at the step before (the step that fails at its time step closes no budget)
  const std::vector<long> steps = historySteps(dir.path / "run" / "history.csv");
  REQUIRE(!steps.empty());
  CHECK(steps.back() == summarySteps(dir.path / "run" / "summary.toml") - 1);
  CHECK(has(slurp(dir.path / "run" / "summary.toml"), "\nstatus = \"failed\"\n"));
}

TEST_CASE("a run's summary counts what its last output holds", "[app]") {
  // summary.toml's live elements and particles against the cells and points of the files
  // written at the end time (their XML headers), for a run converting elements to particles
  // and one eroding them: each count is the model's, not the converted or eroded ones'.
  for (const char* mode : {"sph", "erosion"}) {
    CAPTURE(mode);
    const TempFolder dir(std::string("summary_counts_") + mode);
    const Result r =
        runTestScene(std::string("--set 'conversion.mode=\"") + mode + "\"'", dir.path);
    INFO(r.out);
    REQUIRE(r.code == 0);
    const std::string summary = slurp(dir.path / "run" / "summary.toml");
    const auto value = [&](const std::string& key) {
      std::smatch m;
      REQUIRE(std::regex_search(summary, m, std::regex("\n" + key + " = ([0-9]+)\n")));
      return std::stol(m[1]);
    };
    const auto header = [&](const char* file, const std::string& count) {
      std::smatch m;
      const std::string text = slurp(dir.path / "run" / file).substr(0, 2000);
      REQUIRE(std::regex_search(text, m, std::regex(count + "=\"([0-9]+)\"")));
      return std::stol(m[1]);
    };
    const long changed = value("converted") + value("eroded");
    CHECK(changed > 20);
    CHECK(value("live_elements") == value("elements") - changed);
    CHECK(value("live_elements") == header("elements_000004.vtu", "NumberOfCells"));
    CHECK(value("particles") == header("particles_000004.vtp", "NumberOfPoints"));
  }
}

TEST_CASE("a run that fails at its first step keeps its start, written once", "[app]") {
  // A floor above the first step's dt: the state it stopped in is the start, which is the
  // series' first output already, so the series holds that one output (ParaView would show
  // two at t = 0), and the history one row.
  const TempFolder dir("failed_first_step");
  const Result r = runTestScene("--set simulation.dt_min=1e-6", dir.path);
  INFO(r.out);
  REQUIRE(r.code == 1);
  CHECK(has(r.out, "run stopped at t = 0 s, step 0"));
  CHECK(occurrences(slurp(dir.path / "run" / "elements.pvd"), "<DataSet") == 1);
  CHECK(occurrences(slurp(dir.path / "run" / "particles.pvd"), "<DataSet") == 1);
  CHECK(historySteps(dir.path / "run" / "history.csv") == std::vector<long>{0});
}

TEST_CASE("a continued run that fails at once writes no output or history row twice", "[app]") {
  // A run to 1 us with its checkpoint there (its last output and history row at that step),
  // continued to 2 us under a time step floor it falls under at once: the state it stopped
  // in is the checkpoint's, already in the series and the history. Each output time and
  // each history step once (the row was written twice up to the thirty-fourth session).
  const TempFolder dir("failed_restart");
  REQUIRE(runTestScene("--set simulation.end_time=1e-6 --set output.checkpoint_interval=1e-6",
                       dir.path).code == 0);
  std::vector<fs::path> checkpoints;
  for (const auto& entry : fs::directory_iterator(dir.path / "run"))
    if (entry.path().filename().string().rfind("checkpoint_", 0) == 0)
      checkpoints.push_back(entry.path());
  REQUIRE(checkpoints.size() == 1);
  const Result r = command("run --restart " + checkpoints[0].string() +
                               " --set simulation.end_time=2e-6 --set simulation.dt_min=1e-6 "
                               "--quiet --no-images",
                           dir.path);
  INFO(r.out);
  REQUIRE(r.code == 1);
  CHECK(has(r.out, "run stopped at t = "));
  const std::string pvd = slurp(dir.path / "run" / "elements.pvd");
  CHECK(occurrences(pvd, "<DataSet") == 2);  // 0 and 1 us
  CHECK(occurrences(pvd, "timestep=\"1e-06\"") == 1);
  const std::vector<long> steps = historySteps(dir.path / "run" / "history.csv");
  REQUIRE(steps.size() >= 2);
  CHECK(std::adjacent_find(steps.begin(), steps.end(), std::greater_equal<long>()) == steps.end());
}

TEST_CASE("the history takes every n-th step from the start, and the last once", "[app]") {
  // Reference: README, [output] history_every: rows at steps 0, n, 2n, ... and at the last
  // budget (the step before the run's last: a step closes the budget of its start), so a plot
  // of the history reaches the run's end, each step once. Each row's step is its time's (up to
  // the thirty-seventh session the rows said the step after). The test scene: n = 5; to 4 us
  // it ends at step 119, its last budget between two rows' steps; to 3.1 us at step 96, on
  // one (whose row was written twice up to the thirty-fourth session).
  for (const char* end : {"4e-6", "3.1e-6"}) {
    CAPTURE(end);
    const TempFolder dir("history_rows");
    const Result r = runTestScene(std::string("--set simulation.end_time=") + end, dir.path);
    INFO(r.out);
    REQUIRE(r.code == 0);
    const std::vector<long> steps = historySteps(dir.path / "run" / "history.csv");
    const long last = summarySteps(dir.path / "run" / "summary.toml");
    // the two cases this test is for (another solver may need other end times here)
    INFO("the last step " << last << " must fall " << (end[0] == '4' ? "between" : "on")
                          << " the rows' steps");
    REQUIRE(((last - 1) % 5 == 0) == (end[0] != '4'));
    REQUIRE(steps.size() >= 5);
    std::vector<long> expected;
    for (long s = 0; s < last - 1; s += 5) expected.push_back(s);
    if (expected.back() != last - 1) expected.push_back(last - 1);
    CHECK(steps == expected);
    // The time of each row is its step's: the series' output at the end time is step `last`,
    // one dt after the last row.
    const std::string history = slurp(dir.path / "run" / "history.csv");
    const std::string last_row = history.substr(history.rfind('\n', history.size() - 2) + 1);
    const double dt = std::stod(last_row.substr(last_row.find(',', last_row.find(',') + 1) + 1));
    CHECK(std::stod(last_row) + dt == Approx(std::stod(end)).epsilon(1e-9));
  }
}

TEST_CASE("a run folder's scene reruns as it ran, a --set over its resolution preset too",
          "[app]") {
  TempFolder dir("cli_rerun");
  // The test scene with a preset that coarsens the plate, and a --set that refines it again.
  std::string text = slurp(std::string(FESPH_TEST_APP_DIR) + "/shell_scene.toml");
  text.insert(text.find("\n[simulation]"), "\nresolution = \"coarse\"\n");
  text += "\n[resolutions.coarse]\n\"bodies.plate.shape.mesh_size\" = 2e-3\n";
  std::ofstream(dir.path / "preset.toml") << text;
  const auto elements = [&](const std::string& run) {
    std::smatch m;
    const std::string summary = slurp(dir.path / run / "summary.toml");
    REQUIRE(std::regex_search(summary, m, std::regex("\nelements = ([0-9]+)\n")));
    return std::stol(m[1]);
  };
  const std::string quick = " --end-time 1e-7 --quiet --no-images --out ";
  REQUIRE(command("run preset.toml" + quick + "coarse", dir.path).code == 0);
  REQUIRE(command("run preset.toml --set bodies.plate.shape.mesh_size=1e-3" + quick + "fine",
                  dir.path)
              .code == 0);
  REQUIRE(elements("fine") > elements("coarse"));  // the --set won over the preset
  // The run folder's scene.toml alone gives the run it holds: the preset read with it again
  // does not undo the --set.
  REQUIRE(command("run fine/scene.toml" + quick + "again", dir.path).code == 0);
  CHECK(elements("again") == elements("fine"));
}

TEST_CASE("a jacketed bullet from one .msh: its core and jacket of their materials, tied",
          "[app]") {
  // The shell scene's projectile as a bullet meshed in one file (tests/app/jacketed_bullet.msh,
  // in mm): a steel core in a copper jacket, one body of two physical volumes, each given its
  // material. The meshing log gives each volume's tets and mass; the shell's mesh info both
  // materials. Masses: core 3 x 3 x 6 mm of steel_4340 (7830 kg/m^3) 0.4228 g, jacket 162
  // mm^3 of OFHC_copper (8960 kg/m^3) 1.452 g.
  const TempFolder dir("jacketed_bullet");
  fs::copy_file(std::string(FESPH_TEST_APP_DIR) + "/jacketed_bullet.msh",
                dir.path / "bullet.msh");
  std::string scene = slurp(std::string(FESPH_TEST_APP_DIR) + "/shell_scene.toml");
  const auto from = scene.find("name = \"projectile\"");
  const auto to = scene.find("[[bodies]]", from);
  REQUIRE(to != std::string::npos);
  scene.replace(from, to - from,
                "name = \"projectile\"\nmaterials = { core = \"steel_4340\", jacket = "
                "\"OFHC_copper\" }\nprojectile = true\nvelocity = [0.0, 0.0, -600.0]\n"
                "position = [0.0, 0.0, 0.3e-3]\n[bodies.shape]\ntype = \"msh\"\n"
                "file = \"bullet.msh\"\nscale = 1e-3\n\n");
  std::ofstream(dir.path / "scene.toml") << scene;
  const Result run = command("run scene.toml --end-time 1e-6 --out run", dir.path);
  INFO(run.out);
  REQUIRE(run.code == 0);
  CHECK(has(run.out, "body 'projectile': 125 nodes, 384 tets, 6 x 6 x 6 mm, 1.874 g"));
  CHECK(has(run.out, "    volume 'core': 96 tets of steel_4340, 0.4228 g\n"));
  CHECK(has(run.out, "    volume 'jacket': 288 tets of OFHC_copper, 1.452 g\n"));
  std::ofstream(dir.path / "script") << "load scene.toml\nmesh info\n";
  const Result shell = command("shell < script", dir.path);
  INFO(shell.out);
  std::istringstream lines(shell.out);
  std::string projectile;
  for (std::string l; std::getline(lines, l);)
    if (l.rfind("projectile ", 0) == 0) projectile = l;
  CHECK(has(projectile, " steel_4340+OFHC_copper "));
  CHECK(has(projectile, " 384       125 "));
}

TEST_CASE("a plate made of particles: the run draws it and measures it from its particles",
          "[app]") {
  // A plate made of particles has no elements. Its images are its particles, coloured by the
  // field, and its holes are found from them (findParticleHoles); until the forty-second
  // session such a plate was not drawn and had no holes, and the run, the report, compare and
  // the shell said so. The shell scene's plate as particles (its rim hold, which needs
  // elements, left out), 1 us in: the plate is struck but not holed.
  const TempFolder dir("particle_plate");
  std::string scene = slurp(std::string(FESPH_TEST_APP_DIR) + "/shell_scene.toml");
  scene = scene.substr(0, scene.find("[[boundary]]"));
  const std::string plate = "name = \"plate\"\n";
  scene.replace(scene.find(plate), plate.size(), plate + "discretisation = \"sph\"\n");
  std::ofstream(dir.path / "scene.toml") << scene;
  const Result run = command("run scene.toml --end-time 1e-6 --out run", dir.path);
  INFO(run.out);
  REQUIRE(run.code == 0);
  CHECK(!has(run.out, "images not drawn"));
  CHECK(!has(run.out, "plates: none drawn"));
  for (const char* png : {"plate_front.png", "plate_rear.png", "section.png", "velocity.png"})
    CHECK(fs::exists(dir.path / "run" / "images" / png));
  CHECK(fs::exists(dir.path / "run" / "images" / "debris.csv"));
  // The plate is not its own debris (it was listed as a clump of free particles).
  CHECK(has(run.out, "(0 clumps of free particles, 0 would strike a plate)"));
  CHECK(slurp(dir.path / "run" / "images" / "debris.csv").find("\n1e-06,plate,") ==
        std::string::npos);
  // The tables are of the step drawn (they said t = -1 s, the "last" they were asked for);
  // the plate is in holes.json, with no hole (no spurious gap between its particles).
  const std::string holes = slurp(dir.path / "run" / "images" / "holes.json");
  CHECK(has(holes, "\"time_s\": 1e-06"));
  CHECK(has(holes, "{\"name\": \"plate\", \"count\": 0,"));
  const Result at_start = command("render run --time 0 --size 64x64", dir.path);
  INFO(at_start.out);
  CHECK(at_start.code == 0);
  CHECK(fs::exists(dir.path / "run" / "images" / "t_0" / "plate_front.png"));
  CHECK(has(slurp(dir.path / "run" / "images" / "t_0" / "holes.json"), "\"time_s\": 0,"));
  // The report shows the plate's images and says it has no hole.
  const Result report = command("report run --out report", dir.path);
  INFO(report.out);
  REQUIRE(report.code == 0);
  const std::string md = slurp(dir.path / "report" / "report.md");
  CHECK(has(md, "plate_front.png)"));
  CHECK(has(md, "No through-holes"));
  CHECK(!has(md, "No plate images"));
  CHECK(!has(md, "Debris at t = "));  // the plate is no debris
  // fesph compare measures the plate from its particles: a 4 mm hole in the photograph, none
  // in the plate.
  writeDiscPhoto(dir.path / "photo.pgm");
  const Result compared =
      command("compare run --image photo.pgm --mm-per-px 0.1 --center 50,50", dir.path);
  INFO(compared.out);
  CHECK(compared.code == 0);
  CHECK(!has(compared.out, "has neither"));
  CHECK(has(compared.out, "simulation: 0 holes"));
  // The shell draws the plate's images. Its mesh info gives
  // the plate's extent by its particles (it gave 0 x 0 x 0: a body of particles has no
  // nodes), and its columns stay aligned under a material id longer than their width.
  std::ofstream(dir.path / "script")
      << "load scene.toml\nrender plate 1\nset bodies.projectile.material=\"OFHC_copper\"\n"
         "mesh info\n";
  const Result shell = command("shell < script", dir.path);
  INFO(shell.out);
  std::istringstream lines(shell.out);
  std::string header, projectile, plate_row;
  for (std::string l; std::getline(lines, l);) {
    if (l.rfind("body ", 0) == 0) header = l;
    if (l.rfind("projectile ", 0) == 0) projectile = l;
    if (l.rfind("plate ", 0) == 0) plate_row = l;
  }
  REQUIRE(!header.empty());
  CHECK(header.find("kind") == projectile.find("projectile", 1));
  CHECK(has(plate_row, " particles "));
  CHECK(has(plate_row, " (its particles' centres)"));
  CHECK(!has(plate_row, "0.00 x 0.00 x 0.00"));
  CHECK(has(shell.out, "plate 'plate' at t = 0 s: 0 through-holes"));
}
