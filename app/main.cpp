// SPDX-License-Identifier: MIT
// fesph: projectiles perforating spaced multi-layer plates with adaptive FE-SPH coupling.
// Sub-commands:
//   run SCENE      mesh and run a scene, writing a ParaView series, histories and images
//   run --restart CHECKPOINT   continue a run from one of its checkpoints
//   render RUN_DIR draw the report images of a finished run
//   shell [SCENE | RUN_DIR]   interactive workbench (also reads a script: fesph shell < steps.txt)
//   compare RUN_DIR --plate N --image PHOTO --mm-per-px S   holes of a photograph vs the run
#include "app/cli_checks.hpp"
#include "app/commands.hpp"
#include "app/shell.hpp"
#include "render/vtk_errors.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress and summary lines appear as they come
  fesph::quietVtk();  // every VTK failure is reported in fesph's words (vtk_errors.hpp)
  CLI::App app{
      "fesph - explicit FE-SPH simulation of projectiles perforating spaced metal plates.\n"
      "Scenes are TOML files in SI units; see scenes/ and README.md."};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("fesph ") + FESPH_VERSION);

  fesph::RunOptions run;
  CLI::App* run_cmd = app.add_subcommand("run", "Mesh and run a scene to its end time");
  CLI::Option* scene_opt =
      run_cmd->add_option("scene", run.scene, "Scene file (TOML)")->check(CLI::ExistingFile);
  run_cmd->add_option("--restart", run.restart,
                      "Continue from a checkpoint (FOLDER/checkpoint_STEP.h5) instead of "
                      "starting a scene; output goes on in the checkpoint's folder")
      ->excludes(scene_opt);
  run_cmd->callback([&] {
    if (run.scene.empty() && run.restart.empty())
      throw CLI::RequiredError("a scene file or --restart CHECKPOINT");
  });
  run_cmd->add_option("--out", run.out, "Output folder (default: the scene's [output].folder)");
  run_cmd->add_option("--end-time", run.end_time, "End time in s (overrides the scene)")
      ->check(fesph::positiveNumber());
  run_cmd->add_option("--threads", run.threads, "OpenMP threads (default: all cores)")
      ->check(fesph::wholeNumber(1, 1024));
  run_cmd->add_option("--set", run.overrides,
                      "Override a scene value, e.g. --set simulation.end_time=2e-5 "
                      "--set bodies.0.velocity=[0,0,-200] (repeatable)");
  run_cmd->add_option("--materials", run.materials,
                      "Material library (default: materials.toml found above the scene)");
  run_cmd->add_flag("--quiet", run.quiet, "No progress display");
  run_cmd->add_flag("--no-images", run.no_images, "Do not render images at the end");

  fesph::RenderOptions render;
  CLI::App* render_cmd =
      app.add_subcommand("render", "Draw plate images, section, velocity plot and hole metrics");
  render_cmd->add_option("run_dir", render.run_dir, "Run folder (holds elements.pvd)")
      ->required()->check(CLI::ExistingDirectory);
  render_cmd->add_option("--time", render.times, "Output time(s) in s (default: the last)")
      ->check(fesph::nonNegativeNumber());
  render_cmd->add_option("--field", render.field, "Cell field to colour by (default damage)");
  render_cmd->add_option("--size", render.size, "Image size WxH in pixels (default 1600x1200)");
  render_cmd->add_option("--out", render.out, "Image folder (default RUN_DIR/images)");

  fesph::ReportOptions report;
  CLI::App* report_cmd = app.add_subcommand(
      "report", "report.md: residual velocities against the experiment, velocity histories, "
                "wall times, plate images and holes of one or more runs");
  report_cmd->add_option("run_dirs", report.run_dirs, "Run folders")
      ->required()->check(CLI::ExistingDirectory);
  report_cmd->add_option("--out", report.out, "Report folder (default: beside the first run)");

  fesph::CompareCommandOptions compare;
  CLI::App* compare_cmd = app.add_subcommand(
      "compare", "Holes in a photograph of a tested plate against the simulated plate");
  compare_cmd->add_option("run_dir", compare.run_dir, "Run folder (holds elements.pvd)")
      ->required()->check(CLI::ExistingDirectory);
  fesph::addCompareOptions(*compare_cmd, compare);

  fesph::ShellOptions shell;
  CLI::App* shell_cmd = app.add_subcommand(
      "shell", "Interactive workbench: load, set, run, step, render, probe (reads scripts too)");
  shell_cmd->add_option("path", shell.path, "Scene file or run folder to load")
      ->check(CLI::ExistingPath);
  shell_cmd->add_option("--out", shell.out, "Output folder of runs (default: the scene's)");
  shell_cmd->add_option("--set", shell.overrides, "Override a scene value (repeatable)");
  shell_cmd->add_option("--materials", shell.materials, "Material library");
  shell_cmd->add_option("--threads", shell.threads,
                        "OpenMP threads of its runs (default: all cores)")
      ->check(fesph::wholeNumber(1, 1024));

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  // The commands report bad input (2) and failed runs (1) themselves; anything else that
  // escapes them is a defect of fesph, said plainly rather than aborting.
  try {
    if (*run_cmd) return fesph::runCommand(run);
    if (*render_cmd) return fesph::renderCommand(render);
    if (*report_cmd) return fesph::reportCommand(report);
    if (*compare_cmd) return fesph::compareCommand(compare);
    if (*shell_cmd) return fesph::shellCommand(shell);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fesph: internal error: %s\n(a defect of fesph, not of the input: please "
                         "report it with the command line)\n", e.what());
    return 3;
  }
  return 2;
}
