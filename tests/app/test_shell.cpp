// SPDX-License-Identifier: MIT
// `fesph shell` end to end on a tiny impact (tests/app/shell_scene.toml, 1332 elements, a few
// tenths of a second a run): a script piped in (load, set, step, run, render, plot, probe,
// export, errors), and an interactive session on a pseudo-terminal (tab completion, history,
// Ctrl-C pausing a run without losing its state).
#include "core/io/checkpoint.hpp"
#include "tests/support/command.hpp"
#include "tests/support/temp_folder.hpp"
#include "tests/support/text.hpp"

#include <catch2/catch.hpp>

#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

using fesph::testing::occurrences;
using fesph::testing::slurp;
using fesph::testing::TempFolder;
namespace fs = std::filesystem;

namespace {

const std::string kScene = std::string(FESPH_TEST_APP_DIR) + "/shell_scene.toml";

using Result = fesph::testing::CommandResult;

Result shell(const std::string& args, const std::string& script, const fs::path& dir) {
  const fs::path script_file = dir / "steps.txt";
  std::ofstream(script_file) << script;
  return fesph::testing::runCommand(std::string(FESPH_BINARY) + " shell " + args + " < " +
                                    script_file.string() + " 2>&1");
}

/// The line of `text` that starts with `prefix` (after blanks); empty if none.
std::string lineWith(const std::string& text, const std::string& prefix) {
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);)
    if (l.find_first_not_of(' ') != std::string::npos &&
        l.compare(l.find_first_not_of(' '), prefix.size(), prefix) == 0)
      return l;
  return "";
}

/// fesph shell on a pseudo-terminal, as a user at a terminal runs it.
class Terminal {
 public:
  Terminal(const std::vector<std::string>& args, const fs::path& home) {
    pid_ = forkpty(&fd_, nullptr, nullptr, nullptr);
    if (pid_ == 0) {
      setenv("HOME", home.c_str(), 1);  // the history file goes there
      setenv("TERM", "xterm", 1);
      std::vector<char*> argv;
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      execv(argv[0], argv.data());
      _exit(127);
    }
  }
  ~Terminal() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    if (fd_ >= 0) close(fd_);
  }
  void send(const std::string& keys) { REQUIRE(write(fd_, keys.data(), keys.size()) == static_cast<ssize_t>(keys.size())); }
  /// Read until `text` appears after what earlier waits consumed; false after `seconds`.
  bool waitFor(const std::string& text, double seconds = 20) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < until) {
      const std::size_t at = out_.find(text, seen_);
      if (at != std::string::npos) {
        seen_ = at + text.size();
        return true;
      }
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, 50) > 0) {
        char buf[4096];
        const ssize_t n = read(fd_, buf, sizeof buf);
        if (n <= 0) return false;
        out_.append(buf, static_cast<std::size_t>(n));
      }
    }
    return false;
  }
  /// Exit status after quit.
  int wait() {
    int status = 0;
    waitFor("\x04never", 2);  // drain
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  const std::string& output() const { return out_; }

 private:
  pid_t pid_ = -1;
  int fd_ = -1;
  std::string out_;
  std::size_t seen_ = 0;
};

}  // namespace

/// A 200 x 200 grey photograph (binary PGM): a bright plate with a dark disc of 20 px radius
/// around the centre.
void writePhoto(const fs::path& path) {
  std::ofstream out(path, std::ios::binary);
  out << "P5\n200 200\n255\n";
  for (int j = 0; j < 200; ++j)
    for (int i = 0; i < 200; ++i)
      out.put(static_cast<char>(std::hypot(i + 0.5 - 100, j + 0.5 - 100) < 20 ? 30 : 200));
}

TEST_CASE("fesph shell: a scripted session gives the expected output and files", "[app][shell]") {
  TempFolder dir("shell_script");
  const fs::path out = dir.path / "run";
  writePhoto(dir.path / "photo.pgm");
  const std::string script =
      "# a scripted session: comments and blank lines are skipped\n"
      "\n"
      "show simulation.end_time\n"
      "set simulation.end_time=3e-6 output.interval=1e-6\n"
      "show simulation.end_time\n"
      "set title=\"Shell test, changed\"\n"
      "show title bodies.plate.shape.thickness bodies.1.name\n"
      "mesh info\n"
      "step 10\n"
      "probe\n"
      "run to 1.5us\n"
      "bogus\n"
      "set nosuch.key=1\n"
      "run\n"
      "render plate plate rear plastic_strain\n"
      "render plate 2\n"
      "plot velocity\n"
      "probe\n"
      "export state\n"
      "compare --image " + (dir.path / "photo.pgm").string() + " --mm-per-px 0.1 --center 100,100\n"
      "export scene " + (dir.path / "changed.toml").string() + "\n"
      "report\n"
      "show\n";
  const Result r = shell(kScene + " --out " + out.string(), script, dir.path);
  INFO(r.out);

  // Errors were reported, the session went on to the end, and the exit code says so.
  CHECK(r.code == 1);
  CHECK(r.out.find("error: unknown command 'bogus'") != std::string::npos);
  CHECK(r.out.find("nosuch") != std::string::npos);
  CHECK(r.out.find("error: plate 2: no such plate; the run has 1 = 'plate'") != std::string::npos);
  REQUIRE(r.out.find("report: " + (dir.path / "report" / "report.md").string()) != std::string::npos);
  CHECK(slurp(out / "summary.toml").find("complete") != std::string::npos);
  CHECK(slurp(dir.path / "report" / "report.md").find("run") != std::string::npos);
  // No prompt and no terminal control sequences from a pipe.
  CHECK(r.out.find("fesph>") == std::string::npos);
  CHECK(r.out.find('\x1b') == std::string::npos);

  CHECK(r.out.find("simulation.end_time = 4e-06\n") != std::string::npos);
  CHECK(r.out.find("simulation.end_time = 3e-06\n") != std::string::npos);
  CHECK(r.out.find("title = \"Shell test, changed\"\n") != std::string::npos);
  CHECK(r.out.find("bodies.plate.shape.thickness = 0.002\n") != std::string::npos);
  CHECK(r.out.find("bodies.1.name = \"plate\"\n") != std::string::npos);
  CHECK(lineWith(r.out, "plate ").find("target") != std::string::npos);  // mesh info
  CHECK(r.out.find("total: 1332 elements") != std::string::npos);
  CHECK(r.out.find(", step 10, dt = ") != std::string::npos);
  std::smatch m;
  // The intact piece's lead before the measuring plane, one gap (the projectile's 6 mm) behind
  // the 2 mm plate: 8.3 mm at the start (the nose 0.3 mm off the plate), less the <= 600 m/s
  // flight of 10 steps; the second probe (3 us) is nearer.
  {
    const std::regex lead("piece's lead    ([0-9.]+) mm before the measuring plane of 'plate'");
    std::vector<double> leads;
    for (auto it = std::sregex_iterator(r.out.begin(), r.out.end(), lead); it != std::sregex_iterator(); ++it)
      leads.push_back(std::stod((*it)[1]));
    REQUIRE(leads.size() == 2);
    CHECK(leads[0] < 8.3);
    CHECK(leads[0] > 8.0);
    CHECK(leads[1] < leads[0] - 0.5);
  }
  // Only `run to 1.5us` ends with such a line after `step 10`: it stops at the first step past.
  {
    const std::string tail = r.out.substr(r.out.find(", step 10, dt = ") + 1);
    REQUIRE(std::regex_search(tail, m, std::regex("\nt = ([0-9.e+-]+) s, step ([0-9]+), dt = ")));
    CHECK(std::stod(m[1]) >= 1.5e-6);
    CHECK(std::stod(m[1]) < 1.6e-6);
  }
  CHECK(r.out.find("End time reached: t = 3e-06 s") != std::string::npos);

  // Probe: the projectile has slowed down from 600 m/s, and the budget is printed.
  REQUIRE(occurrences(r.out, "projectile 'projectile'\n") == 2);
  const std::string last = r.out.substr(r.out.rfind("projectile 'projectile'\n"));
  REQUIRE(std::regex_search(last, m, std::regex("\\|v\\| ([0-9.]+) m/s")));
  CHECK(std::stod(m[1]) < 590);
  CHECK(std::stod(m[1]) > 300);
  CHECK(last.find("energy (J)      kinetic ") != std::string::npos);
  CHECK(last.find("balance error ") != std::string::npos);

  // Files: the series at the scene's cadence (0, 1, 2, 3 us), the images, the export.
  CHECK(occurrences(slurp(out / "elements.pvd"), "<DataSet") == 4);
  CHECK(fs::file_size(out / "shell" / "t_3e-06" / "plate_rear.png") > 1000);
  CHECK(fs::file_size(out / "shell" / "t_3e-06" / "plate_front.png") > 1000);
  CHECK(fs::file_size(out / "shell" / "velocity.png") > 1000);
  CHECK(occurrences(slurp(out / "export" / "t_3e-06" / "elements.pvd"), "<DataSet") == 1);
  CHECK(slurp(dir.path / "changed.toml").find("end_time = 3e-06") != std::string::npos);
  CHECK(r.out.find("model      t = 3e-06 s of 3e-06 s, step ") != std::string::npos);
  // compare: the photograph's hole of 20 px radius at 0.1 mm/px is 12.57 mm^2.
  CHECK(r.out.find("  photograph: 1 hole\n") != std::string::npos);
  REQUIRE(std::regex_search(r.out, m, std::regex("area +([0-9.]+) mm2")));
  CHECK(std::stod(m[1]) == Approx(M_PI * 4).epsilon(0.03));
  CHECK(r.out.find("  IoU ") != std::string::npos);
  CHECK(fs::exists(out / "shell" / "compare" / "plate_compare_overlay.png"));

  // A run split by the shell ends where `fesph run` ends.
  {
    const std::string cmd = std::string(FESPH_BINARY) + " run " + kScene + " --out " +
                            (dir.path / "plain").string() +
                            " --set simulation.end_time=3e-6 --set output.interval=1e-6 --quiet --no-images";
    const Result run = fesph::testing::runCommand(cmd);
    REQUIRE(run.code == 0);
    const std::string& plain = run.out;
    const std::string v = lineWith(plain, "projectile 'projectile'  mean velocity");
    REQUIRE(!v.empty());
    CHECK(r.out.find(v) != std::string::npos);
    CHECK(r.out.find(lineWith(plain, "steps ")) != std::string::npos);
  }

  // The run folder it left can be looked at (its scene's values, its last output), not run.
  fs::remove_all(out / "shell");
  const Result f = shell(out.string(), "show simulation.end_time\nrender plate 1\nprobe\nrun\n", dir.path);
  INFO(f.out);
  CHECK(f.code == 1);
  CHECK(f.out.find("Run folder " + out.string()) != std::string::npos);
  CHECK(f.out.find("simulation.end_time = 3e-06\n") != std::string::npos);  // with its --set
  CHECK(fs::exists(out / "shell" / "t_3e-06" / "plate_front.png"));
  CHECK(occurrences(f.out, "a run folder holds no model to run or probe") == 2);
}

TEST_CASE("fesph shell: an exported scene holds every digit and character of its values",
          "[app][shell]") {
  TempFolder dir("shell_export");
  const fs::path exported = dir.path / "exported.toml";
  // A time that nine digits do not hold, and a title with a backslash and double quotes (set
  // as a TOML literal string); the scene's velocity, whole numbers written as floats.
  const std::string values = "show simulation.end_time title bodies.0.velocity\n";
  const Result first = shell(kScene + " --out " + (dir.path / "run").string(),
                             "set simulation.end_time=3.0000000000000005e-6 "
                             "title='C:\\runs\\\"q\"'\n" +
                                 values + "export scene " + exported.string() + "\n",
                             dir.path);
  INFO(first.out);
  REQUIRE(first.code == 0);
  CHECK(first.out.find("simulation.end_time = 3.0000000000000005e-06\n") != std::string::npos);
  CHECK(first.out.find("title = \"C:\\\\runs\\\\\\\"q\\\"\"\n") != std::string::npos);
  // The exported scene loads, and shows the same values.
  const Result again = shell(exported.string() + " --out " + (dir.path / "again").string(), values,
                             dir.path);
  INFO(again.out);
  REQUIRE(again.code == 0);
  CHECK(again.out.find(lineWith(first.out, "simulation.end_time = ")) != std::string::npos);
  CHECK(again.out.find(lineWith(first.out, "title = ")) != std::string::npos);
  // Floats stay floats, whole ones too (an integer literal past 2^63 would not even parse).
  CHECK(first.out.find("bodies.0.velocity = [0.0, 0.0, -600.0]\n") != std::string::npos);
  CHECK(again.out.find("bodies.0.velocity = [0.0, 0.0, -600.0]\n") != std::string::npos);
}

TEST_CASE("fesph shell: show and export give the preset's values, and the changes over them",
          "[app][shell]") {
  TempFolder dir("shell_preset");
  // The test scene with a resolution preset that sets the plate's two mesh sizes.
  std::string text = slurp(kScene);
  text.insert(text.find("\n[simulation]"), "\nresolution = \"coarse\"\n");
  text += "\n[resolutions.coarse]\n\"bodies.plate.shape.mesh_size\" = 2e-3\n"
          "\"bodies.plate.shape.coarse_size\" = 4e-3\n";
  const fs::path scene = dir.path / "preset.toml", exported = dir.path / "exported.toml";
  std::ofstream(scene) << text;
  const std::string sizes = "show bodies.plate.shape.mesh_size bodies.plate.shape.coarse_size\n";
  const Result first = shell(scene.string() + " --out " + (dir.path / "run").string(),
                             sizes + "set bodies.1.shape.coarse_size=5e-3\n" + sizes +
                                 "export scene " + exported.string() + "\n",
                             dir.path);
  INFO(first.out);
  REQUIRE(first.code == 0);
  // The preset's sizes, then the change made over one of them, by the body's index (a change
  // wins over a preset, as in the run).
  CHECK(occurrences(first.out, "bodies.plate.shape.mesh_size = 0.002\n") == 2);
  const std::size_t preset = first.out.find("bodies.plate.shape.coarse_size = 0.004\n");
  const std::size_t changed = first.out.find("bodies.plate.shape.coarse_size = 0.005\n");
  CHECK(preset != std::string::npos);
  CHECK(changed != std::string::npos);
  CHECK(preset < changed);
  // The exported scene is those values on its own: no preset left to apply over them again.
  CHECK(slurp(exported).find("\nresolution = ") == std::string::npos);
  CHECK(slurp(exported).find("[resolutions") == std::string::npos);
  const Result again = shell(exported.string() + " --out " + (dir.path / "again").string(), sizes,
                             dir.path);
  INFO(again.out);
  REQUIRE(again.code == 0);
  CHECK(again.out.find("bodies.plate.shape.mesh_size = 0.002\n") != std::string::npos);
  CHECK(again.out.find("bodies.plate.shape.coarse_size = 0.005\n") != std::string::npos);
}

TEST_CASE("fesph shell: quoted words, comments and times as they are typed", "[app][shell]") {
  TempFolder dir("shell_words");
  const fs::path scene = dir.path / "my scene.toml";  // a blank in the path
  std::ofstream(scene) << slurp(kScene);
  const std::string script = "load \"" + scene.string() + "\"  # the scene to run\n"
                             "set title=\"a # b\"\n"
                             "show title\n"
                             "run to -1us\n"
                             "run to 1.5e-3ms\n"
                             "set title=\"open\n"
                             "show title\n";
  const Result r = shell("--out " + (dir.path / "run").string(), script, dir.path);
  INFO(r.out);
  CHECK(r.code == 1);  // the two errors
  CHECK(r.out.find("Scene " + scene.string() + ":") != std::string::npos);
  // A # inside quotes is text; after them, a comment.
  CHECK(occurrences(r.out, "title = \"a # b\"\n") == 2);
  CHECK(r.out.find("error: '-1us' is not a time") != std::string::npos);
  CHECK(r.out.find("error: unbalanced double quote") != std::string::npos);
  // 1.5e-3 ms is 1.5 us: the run stops at the first step past it.
  std::smatch m;
  REQUIRE(std::regex_search(r.out, m, std::regex("\nt = ([0-9.e+-]+) s, step ([0-9]+), dt = ")));
  CHECK(std::stod(m[1]) >= 1.5e-6);
  CHECK(std::stod(m[1]) < 1.6e-6);
}

TEST_CASE("fesph shell: checkpoint, run on, restart from it, the same end", "[app][shell]") {
  TempFolder dir("shell_restart");
  const fs::path out = dir.path / "run";
  const std::string script =
      "set simulation.end_time=3e-6\n"
      "run to 1.2us\n"
      "checkpoint\n"
      "run\n"
      "probe\n"
      "restart\n"  // the newest checkpoint of the run: the one above
      "show\n"
      "run\n"
      "probe\n"
      "restart " + (dir.path / "none.h5").string() + "\n";
  const Result r = shell(kScene + " --out " + out.string(), script, dir.path);
  INFO(r.out);
  CHECK(r.code == 1);  // the missing checkpoint
  std::smatch m;
  REQUIRE(std::regex_search(r.out, m, std::regex("(\\S+checkpoint_0+([0-9]+)\\.h5) \\(t = ([0-9.e+-]+) s, step ([0-9]+)\\)")));
  const std::string step = m[4];
  CHECK(m[2] == step);
  CHECK(std::stod(m[3]) >= 1.2e-6);
  CHECK(r.out.find("Restarted at t = " + std::string(m[3]) + " s, step " + step + " of 3e-06 s") != std::string::npos);
  CHECK(r.out.find("model      t = " + std::string(m[3]) + " s of 3e-06 s, step " + step) != std::string::npos);
  // The change the checkpoint's scene lists is the one made before it, as it was typed.
  CHECK(r.out.find("\nchanged    simulation.end_time=3e-6\n") != std::string::npos);
  // The probe after the restarted run equals the probe after the straight one, line by line.
  const std::size_t first = r.out.find("projectile 'projectile'\n");
  const std::size_t second = r.out.find("projectile 'projectile'\n", first + 1);
  REQUIRE(second != std::string::npos);
  const auto block = [&](std::size_t at) { return r.out.substr(at, r.out.find("balance error", at) - at); };
  CHECK(block(first) == block(second));
  CHECK(r.out.find("none.h5") != std::string::npos);
}

TEST_CASE("fesph shell: a run paused at times of the user's is the run straight through",
          "[app][shell]") {
  // Reference: `help run`: the steps are not shortened to land on a pause's time, so pausing
  // (run to, run for, step) changes no step. The series written at the scene's interval and
  // the history, byte for byte, against one `run` to the end.
  TempFolder dir("shell_pauses");
  const fs::path paused = dir.path / "paused", straight = dir.path / "straight";
  const Result a = shell(kScene + " --out " + paused.string(),
                         "run to 1.1us\nstep 3\nrun for 0.77us\nrun to 2.5e-6\nrun\n", dir.path);
  const Result b = shell(kScene + " --out " + straight.string(), "run\n", dir.path);
  INFO(a.out << "\n----\n" << b.out);
  REQUIRE(a.code == 0);
  REQUIRE(b.code == 0);
  for (const char* file : {"elements_000001.vtu", "elements_000004.vtu", "particles_000004.vtp",
                           "history.csv", "residual_velocities.csv"}) {
    INFO(file);
    REQUIRE(fs::exists(straight / file));
    CHECK(slurp(paused / file) == slurp(straight / file));
  }
}

/// The `key = value` line of summary.toml in `folder`, value only; empty if none.
std::string summaryValue(const fs::path& folder, const std::string& key) {
  const std::string line = lineWith(slurp(folder / "summary.toml"), key + " = ");
  return line.empty() ? "" : line.substr(key.size() + 3);
}

TEST_CASE("fesph shell: the run folder's summary says where the run stands and when it failed",
          "[app][shell]") {
  // summary.toml's status is what `fesph report` shows (paused, complete, failed); a shell run
  // used to leave the "running" of its last field output there, whatever became of it.
  TempFolder dir("shell_status");
  const fs::path out = dir.path / "run";
  // `run to` a time already passed and `run for 0` take no step and say so.
  const Result paused = shell(kScene + " --out " + out.string(),
                              "step 6\nprobe\nrun to 1e-9\nrun for 0\nrun to 0.05us\n", dir.path);
  INFO(paused.out);
  CHECK(paused.code == 1);
  CHECK(occurrences(paused.out, "the model is at t = ") == 2);
  CHECK(paused.out.find("run for T: T must be > 0") != std::string::npos);
  CHECK(summaryValue(out, "status") == "\"paused\"");
  CHECK(summaryValue(out, "steps") == "6");
  // The probe's energies are the budget of step 5 (the sixth step closed it), and say so:
  // history.csv's row of step 5 (history_every = 5) holds the same kinetic energy.
  std::smatch m;
  REQUIRE(std::regex_search(paused.out, m, std::regex("kinetic ([0-9.e+-]+) ")));
  const double kinetic = std::stod(m[1]);
  CHECK(paused.out.find(", step 5: a step closes the budget of its start") != std::string::npos);
  const std::string history = slurp(out / "history.csv");
  REQUIRE(std::regex_search(history, m,
                            std::regex("\n[^,]+,5,[^,]+,([^,]+),")));  // time,step,dt,kinetic
  CHECK(std::stod(m[1]) == Approx(kinetic).epsilon(1e-5));  // the probe prints 6 digits

  // --threads as fesph run's (the shell had none: its runs took every core). One thread is
  // the default here (as under ctest), so 2 comes from the option.
  setenv("OMP_NUM_THREADS", "1", 1);
  const Result complete =
      shell(kScene + " --out " + out.string() + " --threads 2", "run\n", dir.path);
  INFO(complete.out);
  CHECK(complete.code == 0);
  CHECK(summaryValue(out, "status") == "\"complete\"");
  CHECK(summaryValue(out, "threads") == "2");
  const Result no_threads = shell(kScene + " --threads 0", "run\n", dir.path);
  INFO(no_threads.out);
  CHECK(no_threads.code == 2);
  CHECK(no_threads.out.find("--threads: expected a whole number from 1 to 1024, got '0'") !=
        std::string::npos);

  // A time step floor the impact crosses after a few steps: the message gives the time it
  // stopped at (it said "t = 0.000001 s" for 5.35e-7 s), the summary the same time.
  const Result failed =
      shell(kScene + " --out " + out.string(), "set simulation.dt_min=3e-8\nrun\n", dir.path);
  INFO(failed.out);
  CHECK(failed.code == 1);
  CHECK(summaryValue(out, "status") == "\"failed\"");
  const std::string time = summaryValue(out, "time");
  REQUIRE(!time.empty());
  CHECK(std::stod(time) > 0);
  REQUIRE(std::regex_search(failed.out, m,
                            std::regex("the run stopped at t = ([0-9.e+-]+) s, step ([0-9]+):")));
  CHECK(std::stod(m[1]) == Approx(std::stod(time)).epsilon(1e-8));  // 9 digits against 10
  CHECK(m[2] == summaryValue(out, "steps"));
  // The folder loaded again says where its run stands.
  const Result shown = shell("", "load " + out.string() + "\nshow\n", dir.path);
  INFO(shown.out);
  CHECK(shown.out.find("run folder " + out.string() + " (no model): failed at t = ") !=
        std::string::npos);
  CHECK(shown.out.find(" of 4e-06 s, step " + summaryValue(out, "steps") + "\n") !=
        std::string::npos);
}

TEST_CASE("fesph shell: a finished run in the folder stays until the shell's own run writes",
          "[app][shell]") {
  // Loading the scene and probing it at t = 0 removed the finished run its folder held (its
  // series and images), and `plot velocity` then drew that run's history as the shell's.
  TempFolder dir("shell_keeps_run");
  const fs::path out = dir.path / "run";
  const std::string first =
      fesph::testing::runCommand(std::string(FESPH_BINARY) + " run " + kScene + " --out " +
                                 out.string() + " --end-time 1e-6 --quiet 2>&1")
          .out;
  INFO(first);
  REQUIRE(fs::exists(out / "elements_000001.vtu"));
  REQUIRE(fs::exists(out / "images" / "plate_front.png"));
  const std::string pvd = slurp(out / "elements.pvd"), summary = slurp(out / "summary.toml");
  // `report RUN_DIR` of that run is one of it: the shell's status is not written over it.
  const Result looked = shell(kScene + " --out " + out.string(),
                              "probe\nplot velocity\nreport\nshow\nreport " + out.string() +
                                  " --out " + (dir.path / "report").string() + "\n",
                              dir.path);
  INFO(looked.out);
  CHECK(looked.out.find("projectile 'projectile'") != std::string::npos);  // the probe ran
  CHECK(occurrences(looked.out, "nothing has run yet: `run` or `step` first") == 2);
  CHECK(looked.out.find("the run there before") == std::string::npos);
  CHECK(slurp(out / "elements.pvd") == pvd);
  CHECK(slurp(out / "summary.toml") == summary);
  CHECK(fs::exists(out / "elements_000001.vtu"));
  CHECK(fs::exists(out / "images" / "plate_front.png"));
  CHECK(fs::exists(dir.path / "report" / "report.md"));
  // A step is the shell's run: it replaces the run there, and says so.
  const Result stepped =
      shell(kScene + " --out " + out.string(), "probe\nstep 2\nplot velocity\n", dir.path);
  INFO(stepped.out);
  CHECK(stepped.code == 0);
  CHECK(stepped.out.find(out.string() + ": the run there before is replaced: its series and "
                                        "histories and 7 files of images/") != std::string::npos);
  CHECK(!fs::exists(out / "elements_000001.vtu"));
  CHECK(!fs::exists(out / "images" / "plate_front.png"));
  CHECK(summaryValue(out, "status") == "\"paused\"");
  // So does a checkpoint, which goes with this run's series and histories.
  fesph::testing::runCommand(std::string(FESPH_BINARY) + " run " + kScene + " --out " +
                             out.string() + " --end-time 1e-6 --quiet --no-images 2>&1");
  const Result saved = shell(kScene + " --out " + out.string(), "checkpoint\n", dir.path);
  INFO(saved.out);
  CHECK(saved.code == 0);
  CHECK(saved.out.find("the run there before is replaced: its series and histories") !=
        std::string::npos);
  CHECK(!fs::exists(out / "elements_000001.vtu"));
  CHECK(fs::exists(out / "checkpoint_000000000.h5"));
}

TEST_CASE("fesph shell: going back past a later checkpoint is refused, --out goes on elsewhere",
          "[app][shell]") {
  TempFolder dir("shell_restart_older");
  const fs::path out = dir.path / "run";
  const Result first = shell(kScene + " --out " + out.string(),
                             "set simulation.end_time=2e-6\nrun to 1us\ncheckpoint\nrun\ncheckpoint\n",
                             dir.path);
  INFO(first.out);
  REQUIRE(first.code == 0);
  const std::vector<std::string> saved = fesph::listCheckpoints(out.string());
  REQUIRE(saved.size() == 2);
  const std::string history = slurp(out / "history.csv");

  // Going back to the older one in its own folder would cut the history the newer one needs.
  const fs::path elsewhere = dir.path / "from_older";
  const Result r = shell("", "restart " + saved[0] + "\nrestart " + saved[0] + " --out " +
                                 elsewhere.string() + "\nrun\nrestart " + saved[1] + "\nprobe\n",
                         dir.path);
  INFO(r.out);
  CHECK(r.code == 1);  // the refused restart
  CHECK(r.out.find("holds a later checkpoint (" + fs::path(saved[1]).filename().string() + ")") !=
        std::string::npos);
  CHECK(r.out.find("output continues in " + elsewhere.string()) != std::string::npos);
  CHECK(slurp(out / "history.csv") == history);  // the run folder's records untouched
  CHECK(fs::exists(elsewhere / "history.csv"));
  CHECK(r.out.find("Restarted at t = 2e-06 s") != std::string::npos);  // the newer one still works
}

TEST_CASE("fesph shell on a terminal: completion, history, Ctrl-C pauses a run", "[app][shell]") {
  TempFolder dir("shell_tty");
  Terminal t({FESPH_BINARY, "shell", kScene, "--out", (dir.path / "run").string()}, dir.path);
  REQUIRE(t.waitFor("fesph> "));
  t.send("load " + std::string(FESPH_TEST_APP_DIR) + "/shell_sc\t\r");  // a file name
  CHECK(t.waitFor("shell_scene.toml: \"Shell test impact\""));
  REQUIRE(t.waitFor("fesph> "));
  t.send("mesh in\t\r");  // completes to `mesh info`
  CHECK(t.waitFor("total: 1332 elements"));
  REQUIRE(t.waitFor("fesph> "));
  t.send("show simulation.end_t\t\r");  // a scene key
  CHECK(t.waitFor("simulation.end_time = 4e-06"));
  REQUIRE(t.waitFor("fesph> "));
  t.send("\x10\r");  // Ctrl-P: the previous line again
  CHECK(t.waitFor("simulation.end_time = 4e-06"));
  REQUIRE(t.waitFor("fesph> "));

  // A long run, paused by Ctrl-C; its state stays and the next `step` goes on from it.
  t.send("set simulation.end_time=1\r");
  REQUIRE(t.waitFor("fesph> "));
  t.send("run\r");
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  t.send("\x03");
  REQUIRE(t.waitFor("Paused (Ctrl-C) at t = "));
  REQUIRE(t.waitFor(", step "));
  REQUIRE(t.waitFor("fesph> "));
  const std::string before = t.output();
  std::smatch m;
  REQUIRE(std::regex_search(before, m, std::regex("Paused \\(Ctrl-C\\) at t = [0-9.e+-]+ s, step ([0-9]+)")));
  const long paused = std::stol(m[1]);
  CHECK(paused > 0);  // how far it got in 0.8 s depends on the machine
  t.send("step 3\r");
  REQUIRE(t.waitFor("s, step " + std::to_string(paused + 3) + ", dt = "));
  REQUIRE(t.waitFor("fesph> "));
  // Ctrl-C at the prompt clears the line and does not end the session.
  t.send("probe-not-sent\x03");
  REQUIRE(t.waitFor("fesph> "));
  t.send("help step\r");
  CHECK(t.waitFor("advance N steps"));
  REQUIRE(t.waitFor("fesph> "));
  t.send("quit\r");
  CHECK(t.wait() == 0);
  CHECK(t.output().find("unknown command") == std::string::npos);
  CHECK(fs::exists(dir.path / ".fesph_history"));
}
