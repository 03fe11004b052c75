// SPDX-License-Identifier: MIT
// `fesph run`: read the scene, mesh it, run the time loop with output at the scene's cadence,
// and print a summary with figures of merit. Output files stay valid if the run fails.
#include "app/commands.hpp"
#include "app/progress.hpp"
#include "app/run_session.hpp"
#include "app/stop_signal.hpp"

#include "core/common/error.hpp"

#include <omp.h>

#include <cstdio>
#include <cstring>
#include <iostream>

namespace fesph {

void useThreads(int threads) {
  if (threads > 0) omp_set_num_threads(threads);
  // More threads than cores take turns at every barrier of a step (~25 a step): a run can
  // take several times as long, with the same results.
  if (threads > omp_get_num_procs())
    std::fprintf(stderr,
                 "warning: --threads %d is more than the %d core%s this run may use: the "
                 "threads take turns, which is slower (the results are the same)\n",
                 threads, omp_get_num_procs(), omp_get_num_procs() == 1 ? "" : "s");
}

namespace {

/// A time typed in seconds where microseconds were meant (30 for 30e-6) shows in the first
/// step: a run of billions of steps, and a log without a progress line for days.
void warnOfManySteps(const Model& m, double end_time) {
  const double steps = (end_time - m.time) / m.dt;
  if (steps > 1e7)
    std::fprintf(stderr,
                 "warning: reaching t = %.6g s takes about %.2g steps at the first step's dt = %.3g s "
                 "(scene times are in seconds: 30e-6 for 30 us)\n",
                 end_time, steps, m.dt);
}

}  // namespace

int runCommand(const RunOptions& opt) {
  std::vector<std::string> overrides = opt.overrides;
  if (opt.end_time > 0) {
    char value[32];  // std::to_string would print 1e-7 as 0.000000
    std::snprintf(value, sizeof value, "%.17g", opt.end_time);
    overrides.push_back(std::string("simulation.end_time=") + value);
  }
  useThreads(opt.threads);
  RunSession session;
  try {
    if (!opt.restart.empty())
      session.restart(opt.restart, overrides, opt.out, &std::cout);
    else
      session.open(opt.scene, overrides, opt.out, opt.materials, &std::cout);
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  } catch (const RunError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }

  const Model& model = session.model();
  const std::string& folder = session.folder();
  std::printf("Running to t = %.6g s, output every %.6g s, %d threads\n", session.endTime(),
              session.scene().output.interval, omp_get_max_threads());
  Progress progress(session.endTime(), !opt.quiet);
  bool first_step = true;
  session.onStep([&](const Model& m) {
    if (first_step) warnOfManySteps(m, session.endTime());
    first_step = false;
    progress.update(m.time, m.step, m.dt);
  });
  int code = 0;
  const StopReason why = session.advance(session.endTime(), -1, installStopSignals());
  if (why == StopReason::Failed) {
    progress.finish();
    std::fprintf(stderr,
                 "error: run stopped at t = %.6g s, step %ld: %s\n"
                 "Output written so far is valid and kept in %s\n",
                 model.time, model.step, session.failure().c_str(), folder.c_str());
    code = 1;
  } else if (why == StopReason::Interrupted) {
    progress.finish();
    code = 1;
    try {
      const std::string path = session.checkpoint();
      std::fprintf(stderr,
                   "interrupted (%s) at t = %.6g s, step %ld: checkpoint written to %s\n"
                   "Continue with: fesph run --restart %s\n",
                   strsignal(stopSignal()), model.time, model.step, path.c_str(), path.c_str());
    } catch (const RunError& e) {
      std::fprintf(stderr, "interrupted at t = %.6g s, step %ld; no checkpoint: %s\n",
                   model.time, model.step, e.what());
    }
  }
  progress.finish();
  session.printSummary();
  try {
    session.writeSummary(folder + "/summary.toml", why == StopReason::Failed        ? "failed"
                                                   : why == StopReason::Interrupted ? "interrupted"
                                                                                    : "complete");
  } catch (const RunError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    code = 1;
  }
  if (!opt.no_images && why != StopReason::Interrupted) {
    // A failed image must not fail a finished run: warn and keep the exit code.
    std::printf("Images\n");
    try {
      renderRun(folder, -1.0, "damage", 1600, 1200, folder + "/images");
    } catch (const RunError& e) {
      std::fprintf(stderr, "warning: images not drawn: %s\n", e.what());
    }
  }
  return code;
}

}  // namespace fesph
