// SPDX-License-Identifier: MIT
// The particles' spatial renumbering: a permutation that groups bodies and follows space, that
// carries every particle array with its particle, and that leaves the next step's forces what
// they were (up to the order of the sums).
#include "core/solver/step.hpp"
#include "core/sph/particle_body.hpp"
#include "core/sph/particle_order.hpp"

#include "tests/support/models.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <numeric>
#include <random>

using namespace fesph;
using fesph::testing::lattice;

namespace {

std::vector<Vec3> shuffled(std::vector<Vec3> x, unsigned seed) {
  std::shuffle(x.begin(), x.end(), std::mt19937(seed));
  return x;
}

/// Two particle bodies, each a lattice numbered in random order, squeezed so that stress,
/// volumes and the artificial terms are not trivial.
Model shuffledBodies() {
  Model m;
  m.materials.push_back(fesph::testing::elasticMaterial());
  const double s = 0.5e-3;
  const std::vector<Vec3> a = shuffled(lattice(Vec3::Zero(), 12, 12, 12, s), 1);
  const std::vector<Vec3> b = shuffled(lattice(Vec3(0, 0, 12 * s), 10, 10, 10, s), 2);
  addParticleBody(m, "a", a, std::vector<double>(a.size(), s * s * s), 0, Vec3(0, 0, 50), true,
                  1.2);
  addParticleBody(m, "b", b, std::vector<double>(b.size(), s * s * s), 0, Vec3(0, 0, -50),
                  false, 1.2);
  Particles& pa = m.particles;
  for (std::size_t i = 0; i < pa.size(); ++i) pa.v[i] += 1e4 * Vec3(-pa.x[i].x(), 0, 0);
  m.sph.controls.order_interval = 0;  // the tests renumber themselves
  return m;
}

double meanStep(const std::vector<Vec3>& x) {
  double sum = 0;
  for (std::size_t k = 1; k < x.size(); ++k) sum += (x[k] - x[k - 1]).norm();
  return sum / static_cast<double>(x.size() - 1);
}

}  // namespace

TEST_CASE("spatialOrder: a permutation by body, along space, stable once ordered",
          "[unit][sph][order]") {
  Model m = shuffledBodies();
  const Particles& pa = m.particles;
  const std::vector<int> order = spatialOrder(pa);
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> identity(pa.size());
  std::iota(identity.begin(), identity.end(), 0);
  REQUIRE(sorted == identity);
  for (std::size_t k = 1; k < order.size(); ++k) REQUIRE(pa.body[order[k - 1]] <= pa.body[order[k]]);

  // Consecutive particles are neighbours: a Z curve steps one spacing (0.5 mm) at a time
  // with a jump at the end of each block (1.51 spacings on average here); the random
  // numbering jumps across the body (0.66 of a 6 mm cube's side on average: 7.4 spacings).
  std::vector<Vec3> along(pa.size());
  for (std::size_t k = 0; k < order.size(); ++k) along[k] = pa.x[order[k]];
  const double before = meanStep(pa.x), after = meanStep(along);
  INFO("mean distance between consecutive particles: " << before << " m shuffled, " << after
                                                      << " m ordered");
  CHECK(before > 5 * 0.5e-3);
  CHECK(after < 0.5e-3 * 1.6);

  step(m, 1.0);  // the snapshot renumberParticles needs
  renumberParticles(m, order);
  CHECK(spatialOrder(m.particles) == identity);
}

TEST_CASE("renumberParticles carries every particle array and the snapshot with its particle",
          "[unit][sph][order]") {
  Model m = shuffledBodies();
  REQUIRE_THROWS_AS(renumberParticles(m, spatialOrder(m.particles)), std::logic_error);
  for (int k = 0; k < 3; ++k) step(m, 1.0);
  m.particles.tie[5].face = {1, 2, 3};  // a tie travels with its particle too
  m.particles.parent[7] = 42;
  const Model before = m;
  std::vector<int> order(m.particles.size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(7));
  renumberParticles(m, order);

  const Particles &a = before.particles, &b = m.particles;
  const SphSnapshot &sa = before.sph.current, &sb = m.sph.current;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t i = static_cast<std::size_t>(order[k]);
    REQUIRE(b.x[k] == a.x[i]);
    REQUIRE(b.v[k] == a.v[i]);
    REQUIRE(b.f[k] == a.f[i]);
    REQUIRE((b.m[k] == a.m[i] && b.V[k] == a.V[i] && b.rho[k] == a.rho[i] && b.h[k] == a.h[i] &&
             b.d0[k] == a.d0[i] && b.dt[k] == a.dt[i]));
    REQUIRE((b.state[k].s.xx == a.state[i].s.xx && b.state[k].p == a.state[i].p &&
             b.state[k].e == a.state[i].e));
    REQUIRE((b.body[k] == a.body[i] && b.material[k] == a.material[i] &&
             b.parent[k] == a.parent[i] && b.tie[k].face == a.tie[i].face && b.id[k] == a.id[i]));
    REQUIRE((sb.x[k] == sa.x[i] && sb.v[k] == sa.v[i] && sb.V[k] == sa.V[i] &&
             sb.B[k] == sa.B[i] && sb.R[k] == sa.R[i] && sb.c[k] == sa.c[i] &&
             sb.tensile[k] == sa.tensile[i]));
  }
  CHECK(m.sph.neighbours.pairs() == 0);  // the last step's pairs are by index: dropped

  // The next step computes the same forces, in another order of the sums: equal to round-off
  // (1e-12 of the largest force; the sums differ in their last bits only).
  Model reference = before;
  step(reference, 1.0);
  step(m, 1.0);
  double f_max = 0, df_max = 0, dx_max = 0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t i = static_cast<std::size_t>(order[k]);
    f_max = std::max(f_max, reference.particles.f[i].norm());
    df_max = std::max(df_max, (m.particles.f[k] - reference.particles.f[i]).norm());
    dx_max = std::max(dx_max, (m.particles.x[k] - reference.particles.x[i]).norm());
  }
  INFO("largest force " << f_max << " N, largest difference " << df_max << " N, positions "
                        << dx_max << " m");
  REQUIRE(f_max > 0);
  CHECK(df_max <= 1e-12 * f_max);
  CHECK(dx_max <= 1e-15);
  CHECK(m.dt == Approx(reference.dt).epsilon(1e-12));
}
