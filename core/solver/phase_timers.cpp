// SPDX-License-Identifier: MIT
#include "core/solver/phase_timers.hpp"

namespace fesph {

const char* phaseName(Phase p) {
  switch (p) {
    case Phase::Conversion: return "conversion";
    case Phase::Elements: return "elements";
    case Phase::Particles: return "particles";
    case Phase::TimeStep: return "time step";
    case Phase::Integrate: return "integration";
    case Phase::Contact: return "contact";
    case Phase::Coupling: return "coupling";
    case Phase::ParticleContact: return "particle contact";
    case Phase::Energy: return "energy";
    case Phase::Count: break;
  }
  return "?";
}

}  // namespace fesph
