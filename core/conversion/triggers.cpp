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

}  // namespace fesph
