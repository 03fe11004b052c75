// SPDX-License-Identifier: MIT
#include "core/conversion/convert.hpp"

#include "core/contact/surfaces.hpp"
#include "core/conversion/erosion.hpp"
#include "core/conversion/ties.hpp"
#include "core/conversion/triggers.hpp"
#include "core/state/model_build.hpp"

#include <cmath>

namespace fesph {

namespace {

void convertElement(Model& model, std::size_t e, double kappa, Trigger why) {
  Elements& el = model.elems;
  const Nodes& nd = model.nodes;
  const double mass = model.materials[el.material[e]].rho0 * el.V0[e];
  Vec3 x_mean = Vec3::Zero(), v_mean = Vec3::Zero();
  for (int a : el.conn[e]) x_mean += 0.25 * nd.x[a], v_mean += 0.25 * nd.v[a];
  double jump = 0;
  for (int a : el.conn[e]) jump += (nd.v[a] - v_mean).squaredNorm();
  jump *= mass / 8.0;

  retireElement(model, e, ElemStatus::Converted);
  appendParticle(model.particles, x_mean, v_mean, mass, el.V[e], std::cbrt(el.V0[e]),
                 kappa * std::cbrt(el.V[e]), el.state[e], el.body[e], el.material[e],
                 static_cast<int>(e));

  // The half-step kinetic energy changes by the jump; the budget books it as converted.
  model.energy.kinetic_half -= jump;
  model.energy.conversion += jump;
  ++model.conversion.converted;
  countTrigger(model.conversion, why);
}

}  // namespace

long convertElements(Model& model, double kappa) {
  long count = 0;
  const std::size_t first_new = model.particles.size();
  for (const auto& [e, why] : triggeredElements(model)) {
    convertElement(model, e, kappa, why);
    ++count;
  }
  // Tie only once every conversion of this call is done: a particle tied at birth to a face
  // of a neighbour that converts later in the same call would be left with a dead tie (released
  // at the next releaseTies, never re-tied) although another face of its element may still
  // bound a live element. The parent's faces are looked up now, against the final surfaces.
  for (std::size_t p = first_new; p < model.particles.size(); ++p)
    tieToExposedFace(model, p, static_cast<std::size_t>(model.particles.parent[p]));
  return count;
}

bool retireInvertedElement(Model& model, std::size_t e) {
  switch (model.controls.conversion.mode) {
    case ConversionMode::Sph:
      convertElement(model, e, model.sph.controls.kappa, Trigger::Safety);
      tieToExposedFace(model, model.particles.size() - 1, e);
      return true;
    case ConversionMode::Erosion:
      erodeElement(model, e, Trigger::Safety);
      return true;
    case ConversionMode::None: break;
  }
  return false;
}

}  // namespace fesph
