// SPDX-License-Identifier: MIT
#include "core/sph/particle_order.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <tuple>
#include <type_traits>

namespace fesph {

namespace {

/// The 21 low bits of v spread to every third bit (bit k to bit 3k).
std::uint64_t spreadBits(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

/// a[k] = a[order[k]] for every k, through `scratch`.
template <class T>
void gather(std::vector<T>& a, const std::vector<int>& order, std::vector<T>& scratch) {
  const long n = static_cast<long>(order.size());
  scratch.resize(order.size());
#pragma omp parallel for schedule(static) if (n > 4096)
  for (long k = 0; k < n; ++k) scratch[k] = a[order[k]];
  a.swap(scratch);
}

/// Every per-particle array of the particles, in the order of their declaration.
template <class Fn>
void forEachArray(Particles& p, Fn&& fn) {
  fn(p.x), fn(p.v), fn(p.f), fn(p.m), fn(p.V), fn(p.rho), fn(p.h), fn(p.d0), fn(p.dt);
  fn(p.state), fn(p.body), fn(p.material), fn(p.parent), fn(p.tie), fn(p.id);
}
static_assert(sizeof(Particles) == 15 * sizeof(std::vector<int>),
              "a new particle array must be renumbered too (forEachArray)");

template <class Fn>
void forEachArray(SphSnapshot& s, Fn&& fn) {
  fn(s.x), fn(s.v), fn(s.h), fn(s.V), fn(s.volume_rate), fn(s.rho), fn(s.c), fn(s.d);
  fn(s.B), fn(s.R), fn(s.tensile);
}
static_assert(sizeof(SphSnapshot) == 11 * sizeof(std::vector<int>),
              "a new snapshot array must be renumbered too (forEachArray)");

}  // namespace

std::vector<int> spatialOrder(const Particles& pa) {
  const std::size_t n = pa.size();
  std::vector<int> order(n);
  if (n == 0) return order;
  Vec3 lo = pa.x[0], hi = pa.x[0];
  for (const Vec3& x : pa.x) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  // 2^21 cells along the box's longest side: far finer than any particle spacing, so the
  // curve orders the particles themselves, not cells of them
  const double extent = std::max((hi - lo).maxCoeff(), 1e-300);
  const double scale = (std::ldexp(1.0, 21) - 1.0) / extent;
  std::vector<std::tuple<int, std::uint64_t, int>> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 c = (pa.x[i] - lo) * scale;
    const std::uint64_t code = spreadBits(static_cast<std::uint64_t>(c.x())) |
                               spreadBits(static_cast<std::uint64_t>(c.y())) << 1 |
                               spreadBits(static_cast<std::uint64_t>(c.z())) << 2;
    key[i] = {pa.body[i], code, static_cast<int>(i)};
  }
  std::sort(key.begin(), key.end());
  for (std::size_t k = 0; k < n; ++k) order[k] = std::get<2>(key[k]);
  return order;
}

void renumberParticles(Model& model, const std::vector<int>& order) {
  Particles& pa = model.particles;
  SphWorkspace& ws = model.sph;
  if (order.size() != pa.size() || ws.current.size() != pa.size())
    throw std::logic_error("renumberParticles: the order or the SPH snapshot does not cover "
                           "every particle");
  const auto renumber = [&order](auto& a) {
    std::remove_reference_t<decltype(a)> scratch;
    gather(a, order, scratch);
  };
  forEachArray(pa, renumber);
  // The snapshot of the last step's forces is the next step's previous configuration.
  forEachArray(ws.current, renumber);
  // Kept by index, and only a cost saving: the next step computes them afresh. Emptied, not
  // freed: fresh pages for the pair arrays cost ~15 us each on this VM
  // (docs/performance-history.md).
  ws.neighbours.offset.clear();
  ws.neighbours.index.clear();
  ws.pair_grad.clear();
  ws.pair_stab.clear();
  ws.search.forgetCandidates();
  ws.yield_cache.clear();
}

bool orderParticlesIfDue(Model& model) {
  const std::size_t n = model.particles.size();
  const long every = model.sph.controls.order_interval;
  if (n == 0 || every <= 0 || model.step % every != 0 || model.sph.current.size() != n)
    return false;
  renumberParticles(model, spatialOrder(model.particles));
  return true;
}

}  // namespace fesph
