// SPDX-License-Identifier: MIT
// When an element stops being an element: the plastic-strain criterion of the paper, full
// damage, and safety criteria that catch a distorting element before it inverts.
#pragma once

#include "core/state/model.hpp"

#include <utility>
#include <vector>

namespace fesph {

/// Why live element e should erode or convert now (None: it stays). Uses the state after the
/// last material update: eps_p, damage, V/V0 and the smallest altitude (the geometric part of
/// the stable step) against its first value.
Trigger elementTrigger(const Model& model, std::size_t e);

/// Every live element whose trigger fires now, ascending, with its trigger: the verdicts the
/// last step's element pass left (Elements::trigger), or where there are none, evaluated here
/// in parallel (each reads only its own element).
std::vector<std::pair<std::size_t, Trigger>> triggeredElements(const Model& model);

/// Count a conversion or erosion under its trigger (plastic strain is the rest).
inline void countTrigger(ConversionStats& stats, Trigger why) {
  if (why == Trigger::Safety) ++stats.by_safety;
  if (why == Trigger::Damage) ++stats.by_damage;
}

}  // namespace fesph
