// SPDX-License-Identifier: MIT
// Wall time of each phase of the step, summed over the run, and the work done (element-steps,
// particle-steps) to turn them into figures of merit. Owned by the Model, filled by step().
#pragma once

#include <array>
#include <chrono>

namespace fesph {

/// The phases of step(), in the order it runs them.
enum class Phase {
  Conversion,  ///< erosion or element -> particle conversion
  Elements,    ///< tet4 kinematics, material, ANP, EOS, bulk viscosity, gather
  Particles,   ///< SPH neighbours, gradients, material and forces
  TimeStep,    ///< stable step
  Integrate,   ///< velocities, fixed components and positions
  Contact,     ///< rigid walls and node-face contact (broad and narrow phase)
  Coupling,    ///< particle-face contact and ties (particles with the elements)
  ParticleContact,  ///< contact between particles of different bodies, symmetry planes
  Energy,      ///< correction work and the energy budget
  Count
};

/// Short name of a phase ("elements", ...).
const char* phaseName(Phase p);

struct PhaseTimes {
  std::array<double, static_cast<int>(Phase::Count)> seconds{};  ///< wall time per phase, s
  double element_steps = 0;   ///< live elements summed over the steps
  double particle_steps = 0;  ///< particles summed over the steps
  long steps = 0;
  double total() const {
    double t = 0;
    for (double s : seconds) t += s;
    return t;
  }
};

/// Books the time since the last lap to a phase: `clock.lap(Phase::Elements)` after each call.
class PhaseClock {
 public:
  explicit PhaseClock(PhaseTimes& times) : times_(times), last_(Clock::now()) {}
  void lap(Phase p) {
    const Clock::time_point now = Clock::now();
    times_.seconds[static_cast<int>(p)] += std::chrono::duration<double>(now - last_).count();
    last_ = now;
  }

 private:
  using Clock = std::chrono::steady_clock;
  PhaseTimes& times_;
  Clock::time_point last_;
};

}  // namespace fesph
