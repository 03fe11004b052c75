// SPDX-License-Identifier: MIT
// SPH solids against physics: elastic wave speed in a slender bar, the copper Taylor bar,
// a bar stretched to 2% (tensile instability), and two colliding bodies that must separate.
#include "core/fem/element_forces.hpp"
#include "core/solver/step.hpp"
#include "core/sph/particle_body.hpp"
#include "core/sph/sph_forces.hpp"
#include "core/sph/sph_workspace.hpp"
#include "core/state/model_build.hpp"

#include "tests/support/models.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

using namespace fesph;
using fesph::testing::lattice;

namespace {

int addLatticeBody(Model& m, const std::string& name, const std::vector<Vec3>& p, double s,
                   const Vec3& v) {
  return addParticleBody(m, name, p, std::vector<double>(p.size(), s * s * s), 0, v, false);
}

using VelocityCondition = std::function<void(Model&, double)>;

/// One step as fesph::step takes it, with the SPH storage kept between steps and a kinematic
/// condition on the particle velocities v^{n+1/2} (rigid walls act on nodes only).
void advance(Model& m, SphWorkspace& ws, const VelocityCondition& bc) {
  const double dt_last = m.dt;
  computeElementForces(m, dt_last);
  computeParticleForces(m, dt_last, ws);
  const double dt = stableTimeStep(m, std::numeric_limits<double>::max());
  const double dt_avg = 0.5 * (dt_last + dt);
  integrateVelocities(m, dt_avg);
  m.v_node_free = m.nodes.v;
  m.v_particle_free = m.particles.v;
  if (bc) bc(m, dt);
  enforceParticleContact(m, dt, ws);
  recordEnergyBudget(m, -correctionWork(m, dt_avg));
  integratePositions(m, dt);
  m.time += dt;
  m.dt = dt;
  ++m.step;
}

/// Frictionless rigid wall z = 0 (normal +z) for particles: a particle that would end the step
/// closer than half its spacing to the wall gets the normal velocity that lands it there
/// (enforceRigidWalls for nodes, offset by the particle's half spacing).
void particleWallZ(Model& m, double dt) {
  Particles& pa = m.particles;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    const double gap_next = pa.x[i].z() + dt * pa.v[i].z() - 0.5 * std::cbrt(pa.V[i]);
    if (gap_next < 0) pa.v[i].z() -= gap_next / dt;
  }
}

/// Smallest distance from each particle to any other of its body, m.
std::vector<double> nearestNeighbourDistances(const Model& m) {
  const Particles& pa = m.particles;
  std::vector<double> d(pa.size(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < pa.size(); ++i)
    for (std::size_t j = 0; j < pa.size(); ++j)
      if (j != i) d[i] = std::min(d[i], (pa.x[i] - pa.x[j]).norm());
  return d;
}

}  // namespace

TEST_CASE("sph elastic bar: the front speed is sqrt(E/rho) within 3%", "[verification][sph]") {
  // A 40 mm x 1.5 mm x 1.5 mm steel bar of 3 x 3 x 80 particles hits a rigid wall at 10 m/s.
  // Reference: elementary bar theory, c = sqrt(E/rho) (the bar is 27 times longer than wide).
  // Front arrival at the station z = 20 mm: the mean velocity of its two particle layers has
  // changed by half of the jump (-v0 -> 0). Tolerance 3%.
  const double L = 40e-3, s = 0.5e-3, v0 = 10.0;
  Model m;
  m.materials.push_back(fesph::testing::elasticMaterial());
  std::vector<Vec3> p = lattice(Vec3::Zero(), 3, 3, 80, s);
  addLatticeBody(m, "bar", p, s, Vec3(0, 0, -v0));
  finaliseModel(m);
  std::vector<std::size_t> station;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (std::abs(p[i].z() - 0.5 * L) < s) station.push_back(i);
  REQUIRE(station.size() == 18);
  const auto stationVelocity = [&] {
    double sum = 0;
    for (std::size_t i : station) sum += m.particles.v[i].z();
    return sum / static_cast<double>(station.size());
  };

  const double c_bar = std::sqrt(m.materials[0].E / m.materials[0].rho0);
  SphWorkspace ws;
  const double arrival = fesph::testing::halfJumpArrival(
      m, v0, 1.5 * (0.5 * L / c_bar), [&] { advance(m, ws, particleWallZ); }, stationVelocity);
  REQUIRE(arrival > 0);
  const double speed = 0.5 * L / arrival;
  INFO("front speed " << speed << " m/s, bar speed " << c_bar << " m/s, error "
                      << (speed - c_bar) / c_bar);
  CHECK(std::abs(speed - c_bar) / c_bar < 0.03);
}

namespace {

/// Nearest-neighbour distances (in spacings, smallest and largest) of a 10 mm x 3 mm x 3 mm
/// elastic steel bar (20 x 6 x 6 particles) stretched at 500/s by its end layers, from a
/// matching linear velocity field, to 2% strain (4 GPa of tension, 40 us: the instability
/// needs this long to grow).
std::pair<double, double> stretchedBarSpacing(bool artificial_stress) {
  const double s = 0.5e-3, L = 10e-3, rate = 500.0;
  Model m;
  m.materials.push_back(fesph::testing::elasticMaterial());
  std::vector<Vec3> p = lattice(Vec3::Zero(), 6, 6, 20, s);
  addLatticeBody(m, "bar", p, s, Vec3::Zero());
  for (std::size_t i = 0; i < p.size(); ++i) m.particles.v[i].z() = rate * (p[i].z() - 0.5 * L);
  finaliseModel(m);
  const auto heldEnds = [&](Model& mm, double) {
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p[i].z() < s || p[i].z() > L - s) mm.particles.v[i].z() = rate * (p[i].z() - 0.5 * L);
  };
  SphWorkspace ws;
  ws.controls.artificial_stress = artificial_stress;
  while (m.time < 0.02 / rate) advance(m, ws, heldEnds);
  const std::vector<double> d = nearestNeighbourDistances(m);
  const auto [lo, hi] = std::minmax_element(d.begin(), d.end());
  return {*lo / s, *hi / s};
}

}  // namespace

TEST_CASE("sph bar stretched to 2% keeps its particles evenly spaced", "[verification][sph]") {
  // Reference: the continuum stays uniform, so every nearest-neighbour distance stays within
  // the elastic change (+2% along, -0.6% across) of the spacing; tolerance 20%. The tensile
  // instability of Eulerian-kernel SPH clumps particles under tension (Swegle et al. 1995);
  // Monaghan's artificial stress (on by default) removes it.
  const auto [lo, hi] = stretchedBarSpacing(true);
  INFO("nearest-neighbour distance " << lo << " .. " << hi << " spacings");
  CHECK(lo > 0.8);
  CHECK(hi < 1.2);
}

TEST_CASE("sph bar stretched to 2% clumps without the artificial stress",
          "[verification][sph][slow]") {
  // The same bar with the remedy off: the check above must fail (it has teeth).
  const auto [lo, hi] = stretchedBarSpacing(false);
  INFO("nearest-neighbour distance " << lo << " .. " << hi << " spacings");
  CHECK(lo < 0.8);
}

TEST_CASE("sph bodies colliding at 200 m/s separate again", "[verification][sph]") {
  // Two 3 mm elastic steel cubes (6^3 particles each) meet at 2 x 100 m/s. Reference: an
  // elastic impact ends in rebound after about twice the wave transit time; the contact is
  // compression only, so nothing holds the bodies together. After 10 transits the centres of
  // mass must move apart, the momentum be unchanged (1e-12 of m v) and the bodies apart.
  const double s = 0.5e-3, a = 3e-3, v = 100.0;
  Model m;
  m.materials.push_back(fesph::testing::elasticMaterial());
  const int b0 = addLatticeBody(m, "left", lattice(Vec3(-a, 0, 0), 6, 6, 6, s), s, Vec3(v, 0, 0));
  const int b1 = addLatticeBody(m, "right", lattice(Vec3(s, 0, 0), 6, 6, 6, s), s, Vec3(-v, 0, 0));
  finaliseModel(m);
  const Vec3 p0 = m.energy.momentum;
  const double scale = 2 * v * m.materials[0].rho0 * a * a * a;
  const double transit = a / std::sqrt(m.materials[0].E / m.materials[0].rho0);
  SphWorkspace ws;
  double min_gap = 1.0;
  while (m.time < 10 * transit) {
    advance(m, ws, nullptr);
    min_gap = std::min(min_gap, particleBodyCentre(m, b1).x() - particleBodyCentre(m, b0).x());
  }
  const double gap = particleBodyCentre(m, b1).x() - particleBodyCentre(m, b0).x();
  const double v_rel = bodyMeanVelocity(m, b1).x() - bodyMeanVelocity(m, b0).x();
  Vec3 p1 = Vec3::Zero();
  for (std::size_t i = 0; i < m.particles.size(); ++i) p1 += m.particles.m[i] * m.particles.v[i];
  INFO("separation velocity " << v_rel << " m/s (approach was " << 2 * v << " m/s), centre gap "
                              << gap << " m (smallest " << min_gap << " m), contact energy "
                              << m.energy.contact << " J");
  REQUIRE((p1 - p0).norm() < 1e-12 * scale);
  CHECK(v_rel > 0.2 * v);
  CHECK(gap > min_gap + 0.1 * s);
}

TEST_CASE("sph Taylor bar: copper final length within 5% of 21.42-21.48 mm",
          "[verification][sph][slow]") {
  // Copper code benchmark (e.g. Zhang et al., SPH Taylor bar; LS-DYNA / SPHinXsys cases):
  // rho 8930, E 117 GPa, nu 0.35, yield 400 MPa, linear hardening tangent 100 MPa, no rate or
  // thermal softening; L0 32.4 mm, R0 3.2 mm, 227 m/s onto a frictionless rigid wall; at 80 us
  // the reference codes give 21.42-21.48 mm. Tolerance 5%. Particles on a 0.72 mm lattice
  // (4.4 per radius, 45 along). Artificial viscosity alpha = 0.1, beta = 0.5 (IMPETUS
  // defaults): the classic 1 / 2 turns a third of the impact energy into viscous heat and
  // leaves the bar 8-13% too long (docs/sph.md).
  Material cu;
  cu.name = "copper (Taylor benchmark)";
  cu.rho0 = 8930;
  cu.E = 117e9;
  cu.nu = 0.35;
  cu.strength = StrengthModel::JohnsonCook;
  const double Et = 100e6;
  cu.A = 400e6;
  cu.B = cu.E * Et / (cu.E - Et);
  cu.n = 1;
  REQUIRE(finaliseMaterial(cu).empty());
  Model m;
  m.materials.push_back(cu);
  const double R0 = 3.2e-3, L0 = 32.4e-3, s = L0 / 45;
  std::vector<Vec3> p;
  for (const Vec3& q : lattice(Vec3(-5 * s, -5 * s, 0), 10, 10, 45, s))
    if (q.head<2>().norm() < R0) p.push_back(q);
  addLatticeBody(m, "bar", p, s, Vec3(0, 0, -227.0));
  finaliseModel(m);
  SphWorkspace ws;
  ws.controls.av_alpha = 0.1;
  ws.controls.av_beta = 0.5;
  while (m.time < 80e-6) advance(m, ws, particleWallZ);

  const Particles& pa = m.particles;
  double top = 0, r_foot = 0;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    top = std::max(top, pa.x[i].z() + 0.5 * std::cbrt(pa.V[i]));
    if (pa.x[i].z() < s) r_foot = std::max(r_foot, pa.x[i].head<2>().norm());
  }
  INFO(pa.size() << " particles, " << m.step << " steps: final length " << top * 1e3
                 << " mm, foot radius " << r_foot * 1e3 << " mm, energy balance error "
                 << m.energy.balanceError() << ", plastic work " << m.energy.plastic_work
                 << " J, artificial viscosity " << m.energy.artificial_viscosity
                 << " J, wall " << m.energy.contact << " J of " << m.energy.initial << " J");
  CHECK(top > 0.95 * 21.42e-3);
  CHECK(top < 1.05 * 21.48e-3);
}
