// SPDX-License-Identifier: MIT
#include "core/conversion/triggers.hpp"

namespace fesph {

Trigger elementTrigger(const Model& model, std::size_t e) {
  const Elements& el = model.elems;
  const ConversionControls& c = model.controls.conversion;
  const PointState& st = el.state[e];
  if (st.eps_p >= c.plastic_strain) return Trigger::PlasticStrain;
  if (st.damage >= 1.0) return Trigger::Damage;
  const double J = el.V[e] / el.V0[e];
  if (J < c.min_volume_ratio || J > c.max_volume_ratio) return Trigger::Safety;
  if (el.len0[e] > 0 && el.len[e] < c.min_dt_ratio * el.len0[e]) return Trigger::Safety;
  return Trigger::None;
}

std::vector<std::pair<std::size_t, Trigger>> triggeredElements(const Model& model) {
  const Elements& el = model.elems;
  std::vector<std::pair<std::size_t, Trigger>> out;
  // The last step's element pass evaluated them on the state they are read from here (not so
  // at a run's first step, nor at the first after a restart): reading all of it again cost
  // ~5 % of an FE-only impact step.
  if (el.trigger_step == model.step - 1 && el.trigger.size() == el.size()) {
    for (std::size_t e = 0; e < el.size(); ++e)
      if (el.trigger[e] != Trigger::None && el.status[e] == ElemStatus::Live)
        out.emplace_back(e, el.trigger[e]);
    return out;
  }
  const long ne = static_cast<long>(el.size());
  std::vector<Trigger> why(el.size(), Trigger::None);
  // Converted elements gather where the projectile went: chunks taken as they come balance
  // the live ones over the threads (each element's verdict is its own).
#pragma omp parallel for schedule(dynamic, 2048)
  for (long e = 0; e < ne; ++e)
    if (el.status[e] == ElemStatus::Live) why[e] = elementTrigger(model, e);
  for (std::size_t e = 0; e < el.size(); ++e)
    if (why[e] != Trigger::None) out.emplace_back(e, why[e]);
  return out;
}

}  // namespace fesph
