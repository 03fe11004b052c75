// SPDX-License-Identifier: MIT
// Adaptive FE -> SPH conversion in running scenes (issue 6; Hu, Sun & Zhu 2015 eqs. 1-12,
// design.md 7): conservation with many conversions, a stress wave through a converted
// segment, particles striking a plate, and bitwise reproducibility.
#include "core/conversion/convert.hpp"
#include "core/conversion/particle_face_contact.hpp"
#include "core/material/library.hpp"
#include "core/mesh/structured_box.hpp"
#include "core/solver/step.hpp"
#include "core/sph/particle_body.hpp"
#include "tests/support/models.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

using namespace fesph;
using fesph::testing::totalMass;
using fesph::testing::totalMomentum;

namespace {

Material copper() {
  const MaterialLibrary lib =
      MaterialLibrary::load(std::string(FESPH_SCENES_DIR) + "/materials.toml");
  return lib.get("copper_taylor_benchmark");
}

// Two copper bars 3 x 3 x 9 mm (3 x 3 x 9 cells each) meeting head-on at +-227 m/s.
Model twoBars(double plastic_strain) {
  Model m;
  m.materials.push_back(copper());
  const Vec3 size(3e-3, 3e-3, 9e-3);
  Placement lower, upper;
  lower.translation = Vec3(0, 0, -9e-3);
  upper.translation = Vec3(0.5e-3, 0.25e-3, 0);  // offset: not a symmetric problem
  addBody(m, "lower", structuredBox(Vec3::Zero(), size, 3, 3, 9), 0, lower, Vec3(0, 0, 227), true);
  addBody(m, "upper", structuredBox(Vec3::Zero(), size, 3, 3, 9), 0, upper, Vec3(0, 0, -227), false);
  finaliseModel(m);
  m.controls.conversion.mode = ConversionMode::Sph;
  m.controls.conversion.plastic_strain = plastic_strain;
  return m;
}

/// An elastic plate 6 x 6 x 1 mm (12 x 12 x 2 cells), centred on the z axis, its top face
/// at z = 0, at rest and free.
Model plateModel() {
  Model m;
  m.materials.push_back(fesph::testing::elasticMaterial());
  Placement plate;
  plate.translation = Vec3(-3e-3, -3e-3, -1e-3);
  addBody(m, "plate", structuredBox(Vec3::Zero(), Vec3(6e-3, 6e-3, 1e-3), 12, 12, 2), 0, plate,
          Vec3::Zero(), false);
  return m;
}

}  // namespace

TEST_CASE("many conversions: a copper bar on a rigid wall keeps mass and the energy budget",
          "[verification][conversion][conservation]") {
  // Reference: issue 6 acceptance: total mass (nodes + particles) constant to 1e-12 relative;
  // energy budget with the conversion term closes within 1 % (balanceError) at every step.
  Model m = fesph::testing::boxModel(copper(), Vec3(4e-3, 4e-3, 16e-3), 4, 4, 16, Vec3(0, 0, -227));
  m.walls.push_back(RigidWall{});
  m.controls.conversion.mode = ConversionMode::Sph;
  m.controls.conversion.plastic_strain = 0.3;
  const double mass0 = totalMass(m);
  double worst = 0, worst_mass = 0;
  while (m.time < 20e-6) {
    step(m, 20e-6);
    worst = std::max(worst, m.energy.balanceError());
    worst_mass = std::max(worst_mass, std::abs(totalMass(m) - mass0) / mass0);
  }
  long live = 0;
  for (ElemStatus s : m.elems.status) live += s == ElemStatus::Live;
  std::printf("[conversion] bar on wall: %ld converted (%ld safety), %zu particles, mass %.2e, "
              "worst balance %.3f %%, conversion term %.3e J of %.3e J\n",
              m.conversion.converted, m.conversion.by_safety, m.particles.size(), worst_mass,
              100 * worst, m.energy.conversion, m.energy.initial);
  REQUIRE(m.conversion.converted > 10);
  REQUIRE(live + m.conversion.converted == static_cast<long>(m.elems.size()));
  REQUIRE(static_cast<long>(m.particles.size()) == m.conversion.converted);
  CHECK(worst_mass < 1e-12);
  CHECK(m.energy.conversion > 0);
  CHECK(worst < 0.01);
}

TEST_CASE("many conversions: two bars colliding conserve momentum", "[verification][conversion][conservation]") {
  // Reference: no wall, no fixed node: every correction (node-face, particle-face, ties,
  // particle contact) and every conversion conserves momentum: |P - P0| < 1e-12 M v0 at every
  // step; mass 1e-12; energy balance within 1 %.
  Model m = twoBars(0.2);
  const double mass0 = totalMass(m);
  const Vec3 p0 = totalMomentum(m);
  const double scale = mass0 * 227.0;
  double worst_p = 0, worst_m = 0, worst_e = 0;
  while (m.time < 12e-6) {
    step(m, 12e-6);
    worst_p = std::max(worst_p, (totalMomentum(m) - p0).norm() / scale);
    worst_m = std::max(worst_m, std::abs(totalMass(m) - mass0) / mass0);
    worst_e = std::max(worst_e, m.energy.balanceError());
  }
  long tied = 0;
  for (const Tie& t : m.particles.tie) tied += t.active();
  std::printf("[conversion] two bars: %ld converted, %ld tied at end, momentum %.2e, mass %.2e, "
              "worst balance %.3f %%\n",
              m.conversion.converted, tied, worst_p, worst_m, 100 * worst_e);
  REQUIRE(m.conversion.converted > 10);
  CHECK(worst_p < 1e-12);
  CHECK(worst_m < 1e-12);
  CHECK(worst_e < 0.01);
}

namespace {

// Elastic steel bar 3 x 3 x 60 mm (1 mm cells) moving at -v0 onto a rigid wall at z = 0.
// Returns the largest rise of the far (top) end's mean velocity above -v0 before 1.5 L/c, m/s,
// and the time it first exceeds half of 2 v0.
struct WaveResult {
  double rise = 0, arrival = 0, balance = 0;
  double plateau = 0;  ///< time-mean of v_top + v0 over [1.1, 1.5] L/c (filters the ringing)
  long particles = 0, tied = 0;
};

WaveResult waveThroughBar(bool convert_middle) {
  const double L = 60e-3, v0 = 5.0;
  Model m = fesph::testing::boxModel(fesph::testing::elasticMaterial(), Vec3(3e-3, 3e-3, L), 3, 3, 60,
                                     Vec3(0, 0, -v0));
  m.walls.push_back(RigidWall{});
  m.controls.conversion.mode = ConversionMode::Sph;
  if (convert_middle) {
    for (std::size_t e = 0; e < m.elems.size(); ++e) {
      double zc = 0;
      for (int a : m.elems.conn[e]) zc += 0.25 * m.nodes.x[a].z();
      if (zc > L / 3 && zc < 2 * L / 3) m.elems.state[e].eps_p = 10.0;
    }
    convertElements(m, m.sph.controls.kappa);
  }
  const Material& mat = m.materials[0];
  const double c = std::sqrt(mat.E / mat.rho0);
  const double t_end = 1.5 * L / c;
  WaveResult r;
  double vmax = -v0, vsum = 0, tsum = 0;
  while (m.time < t_end) {
    step(m, t_end);
    double mv = 0, ms = 0;
    for (std::size_t a = 0; a < m.nodes.size(); ++a)
      if (m.nodes.x0[a].z() > L - 1e-9) mv += m.nodes.m[a] * m.nodes.v[a].z(), ms += m.nodes.m[a];
    const double v = mv / ms;
    vmax = std::max(vmax, v);
    if (m.time > 1.1 * L / c) vsum += (v + v0) * m.dt, tsum += m.dt;
    if (r.arrival == 0 && v > 0) r.arrival = m.time;
    r.balance = std::max(r.balance, m.energy.balanceError());
  }
  r.rise = vmax + v0;
  r.plateau = vsum / tsum;
  r.particles = static_cast<long>(m.particles.size());
  for (const Tie& t : m.particles.tie) r.tied += t.active();
  return r;
}

}  // namespace

TEST_CASE("a stress wave crosses a converted segment of a bar",
          "[verification][conversion][ties]") {
  // Reference: 1D elastic impact of a bar on a rigid wall: the compressive wave reaches the free
  // end at L/c and sets it moving at +v0, a velocity rise of 2 v0 (the all-element bar gives
  // the 3D, discrete value). With the middle third converted to particles (one per tet), the
  // wave has to cross two FE/SPH interfaces; the particles on the interfaces are tied to the
  // exposed element faces (eqs. 6-12), which transmit the compression and the tension across
  // them; inside the segment SPH carries it.
  // Must hold (issue 6): the amplitude that arrives, the time-mean of the far-end velocity over
  // [1.1, 1.5] L/c (the plateau, 2 v0 in 1D), within 10 % of the all-element bar's; energy
  // balance within 1 %. The peak is reported and held to the 1D amplitude within 10 %, not to
  // the all-element peak: that one is the Gibbs overshoot of the discrete FE front, 24 % above
  // 2 v0, which the SPH segment's viscosity smooths away (with the artificial stress off the
  // peak ratio is 0.87 and the plateau ratio 0.98).
  // Measured: plateau ratio 0.931 with the artificial stress on real tension only; 0.812 when
  // it acted on every tensile principal stress (the deviator's excursions in compression).
  const double v0 = 5.0;
  const WaveResult fe = waveThroughBar(false);
  const WaveResult mixed = waveThroughBar(true);
  std::printf("[conversion] wave: all-element rise %.3f m/s (arrival %.2f us), converted middle "
              "third rise %.3f m/s (arrival %.2f us; %ld particles, %ld tied), peak ratio %.3f; plateau "
              "%.3f vs %.3f m/s, ratio %.3f; balance %.3f %% / %.3f %%\n",
              fe.rise, 1e6 * fe.arrival, mixed.rise, 1e6 * mixed.arrival, mixed.particles,
              mixed.tied, mixed.rise / fe.rise, mixed.plateau, fe.plateau,
              mixed.plateau / fe.plateau, 100 * fe.balance, 100 * mixed.balance);
  REQUIRE(mixed.particles > 100);
  REQUIRE(mixed.tied > 0);
  CHECK(fe.rise > 1.8 * v0);  // sanity of the reference run
  CHECK(std::abs(mixed.plateau - fe.plateau) < 0.10 * fe.plateau);
  CHECK(mixed.rise > 0.9 * 2 * v0);  // the front arrives whole
  CHECK(mixed.rise < fe.rise);       // and is not amplified
  CHECK(mixed.balance < 0.01);
}

TEST_CASE("particles fired at a plate stay in front of it", "[verification][conversion][contact]") {
  // Reference: particle-face contact (eqs. 1-5, particle as slave): no particle ends behind a
  // top face it struck, by more than 5 % of its spacing d = cbrt(V); none passes the plate;
  // momentum conserved (no wall, no fixed node) to 1e-12 of M v0.
  const double s = 0.5e-3, v0 = 300.0;
  Model m = plateModel();
  std::vector<Vec3> pts;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) pts.push_back(Vec3((i - 1.5) * s + 0.1e-3, (j - 1.5) * s + 0.05e-3, 0.4e-3 + k * s));
  const int cloud = addParticleBody(m, "cloud", pts, std::vector<double>(pts.size(), s * s * s), 0,
                                    Vec3(0, 0, -v0), true);
  finaliseModel(m);
  const double mass0 = totalMass(m);
  const Vec3 p0 = totalMomentum(m);
  const double scale = 64 * s * s * s * m.materials[0].rho0 * v0;

  double worst_pen = 0, worst_p = 0, min_z = 1e9, min_clear = 1e9;
  const double t_end = 8e-6;
  while (m.time < t_end) {
    step(m, t_end);
    worst_p = std::max(worst_p, (totalMomentum(m) - p0).norm() / scale);
    double plate_bottom = 1e9;
    for (std::size_t a = 0; a < m.nodes.size(); ++a) plate_bottom = std::min(plate_bottom, m.nodes.x[a].z());
    for (std::size_t p = 0; p < m.particles.size(); ++p) {
      const double d = std::cbrt(m.particles.V[p]);
      min_z = std::min(min_z, m.particles.x[p].z() - plate_bottom);
      for (const ExteriorFace& f : m.surfaces.exterior) {
        const Vec3 a = m.nodes.x[f.node[0]], b = m.nodes.x[f.node[1]], c = m.nodes.x[f.node[2]];
        Vec3 n = (b - a).cross(c - a);
        const double area2 = n.squaredNorm();
        n /= std::sqrt(area2);
        if (n.z() < 0.5) continue;  // top faces only
        const Vec3 xp = m.particles.x[p];
        const double dist = (xp - a).dot(n);
        const Vec3 q = xp - dist * n;
        const double w0 = (b - q).cross(c - q).dot(n) / std::sqrt(area2);
        const double w1 = (c - q).cross(a - q).dot(n) / std::sqrt(area2);
        const double w2 = 1 - w0 - w1;
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        if (dist > -0.5e-3) {
          min_clear = std::min(min_clear, dist / d);
          worst_pen = std::max(worst_pen, -dist / d);
        }
      }
    }
  }
  const Vec3 vc = bodyMeanVelocity(m, cloud);
  std::printf("[conversion] cloud on plate: worst penetration %.3f d (closest %.3f d in front), "
              "lowest particle %.3f mm above the plate bottom, momentum %.2e, mass %.2e, cloud "
              "vz %.1f m/s\n",
              worst_pen, min_clear, 1e3 * min_z, worst_p, std::abs(totalMass(m) - mass0) / mass0,
              vc.z());
  CHECK(min_clear < 1.0);  // the particles did reach the plate
  CHECK(worst_pen < 0.05);
  CHECK(min_z > 0);
  CHECK(worst_p < 1e-12);
}

TEST_CASE("the particle-face sweep gives the same pushes for any thread count",
          "[verification][conversion][contact][parallel]") {
  // Reference: issue 11, must hold 1. With one thread the particle-face correction sweeps all
  // particles in order; with more, groups of particles whose faces share no node are swept
  // side by side. Pushes within a group see each other as in the one sweep, so every
  // particle and node velocity must be equal bit for bit (tolerance: none). Three clumps,
  // 3 mm apart, land on a plate at 300 m/s within the step: several groups, each with
  // particles that share faces.
#ifdef _OPENMP
  const double s = 0.25e-3, v0 = 300.0, dt = 1e-7;
  Model m = plateModel();
  std::vector<Vec3> pts;
  for (const Vec3& centre : {Vec3(-1.5e-3, -1.5e-3, 0), Vec3(1.5e-3, 1.5e-3, 0), Vec3(1.5e-3, -1.5e-3, 0)})
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        for (int k = 0; k < 2; ++k)  // the lower layer ends 0.07 mm above the plate, inside the radius
          pts.push_back(centre + Vec3((i - 1.5) * s + 0.03e-3, (j - 1.5) * s + 0.07e-3, 0.1e-3 + k * s));
  addParticleBody(m, "clumps", pts, std::vector<double>(pts.size(), s * s * s), 0, Vec3(0, 0, -v0),
                  true);
  finaliseModel(m);
  const int default_threads = omp_get_max_threads();
  std::vector<Model> results;
  for (int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    results.push_back(m);
    enforceParticleFaceContact(results.back(), dt, 3);
  }
  omp_set_num_threads(default_threads);
  long pushed = 0;
  for (std::size_t p = 0; p < pts.size(); ++p) pushed += results[0].particles.v[p] != m.particles.v[p];
  std::printf("[conversion] particle-face sweep: %ld of %zu particles pushed\n", pushed, pts.size());
  REQUIRE(pushed >= 3 * 16);  // every clump's lower layer struck the plate
  REQUIRE(results[0].nodes.v != m.nodes.v);
  for (const Model& r : results) {
    CHECK(r.particles.v == results[0].particles.v);
    CHECK(r.nodes.v == results[0].nodes.v);
  }
#endif
}

namespace {

struct Snapshot {
  std::vector<Vec3> xn, vn, xp, vp;
  bool operator==(const Snapshot& o) const {
    return xn == o.xn && vn == o.vn && xp == o.xp && vp == o.vp;
  }
};

Snapshot runTwoBars() {
  Model m = twoBars(0.2);
  while (m.time < 8e-6) step(m, 8e-6);
  return {m.nodes.x, m.nodes.v, m.particles.x, m.particles.v};
}

}  // namespace

TEST_CASE("conversion runs are bitwise reproducible", "[verification][conversion][determinism]") {
  // Reference: design requirement: the same scene gives bit-identical nodes and particles,
  // run twice and with 1 or 2 OpenMP threads (tolerance: exact equality).
#ifdef _OPENMP
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
#endif
  const Snapshot a = runTwoBars();
  const Snapshot b = runTwoBars();
  std::printf("[conversion] determinism: %zu particles; repeat identical: %d\n", a.xp.size(),
              static_cast<int>(a == b));
  REQUIRE(a.xp.size() > 10);
  CHECK(a == b);
#ifdef _OPENMP
  omp_set_num_threads(2);
  const Snapshot c = runTwoBars();
  omp_set_num_threads(threads);
  std::printf("[conversion] determinism: 1 vs 2 threads identical: %d\n", static_cast<int>(a == c));
  CHECK(a == c);
#endif
}
