// SPDX-License-Identifier: MIT
#include "core/conversion/erosion.hpp"

#include "core/contact/surfaces.hpp"
#include "core/conversion/triggers.hpp"

namespace fesph {

double retireElement(Model& model, std::size_t e, ElemStatus status) {
  Elements& el = model.elems;
  Nodes& nd = model.nodes;
  const double quarter = 0.25 * model.materials[el.material[e]].rho0 * el.V0[e];
  double kinetic = 0;
  for (int a : el.conn[e]) {
    kinetic += 0.5 * quarter * nd.v[a].squaredNorm();
    // Round-off must not leave a sliver of mass on a node all of whose elements are gone.
    nd.m[a] = nd.m[a] - quarter > 1e-12 * quarter ? nd.m[a] - quarter : 0.0;
  }
  el.status[e] = status;
  removeElementFromSurfaces(model, e);
  return kinetic;
}

void erodeElement(Model& model, std::size_t e, Trigger why) {
  const double mass = model.materials[model.elems.material[e]].rho0 * model.elems.V0[e];
  const double kinetic = retireElement(model, e, ElemStatus::Eroded);
  // The half-step kinetic energy the budget carries loses the same amount, so the average
  // at the next snapshot and the eroded term agree.
  model.energy.kinetic_half -= kinetic;
  model.energy.eroded += kinetic + mass * model.elems.state[e].e;
  model.conversion.eroded_mass += mass;
  ++model.conversion.eroded;
  countTrigger(model.conversion, why);
}

long erodeElements(Model& model) {
  long count = 0;
  for (const auto& [e, why] : triggeredElements(model)) {
    erodeElement(model, e, why);
    ++count;
  }
  return count;
}

}  // namespace fesph
