// SPDX-License-Identifier: MIT
// Figures of merit of the solver loops (Google Benchmark; JSON with --benchmark_format=json).
// Every case takes the thread count as its last argument (1 or 2) and three problem sizes, so
// that the cost per item shows whether it grows linearly. Not a test: run `build/fesph_bench`;
// docs/performance.md says how the figures in it were taken.
//   BM_Stream        memory bandwidth (triad a = b + s c over 3 x 256 MB), bytes/s
//   BM_ElementKernel computeElementForces: tet4 + Johnson-Cook + ANP + EOS + bulk q + gather
//   BM_SphForces     computeParticleForces at ~55 neighbours (Verlet list amortised),
//                    particles in lattice order (order 0), in random order (1), or in random
//                    order renumbered in spatial order every 50 steps, as runs do (2)
//   BM_SphTension    BM_SphForces (lattice) with the cube stretched: every pair in tension
//                    takes the artificial stress, as a third of an impact's particles do
//   BM_SphMirror     BM_SphForces (lattice) with a symmetry plane on one face of the cube: the
//                    cost of the mirror images (compare with BM_SphForces/order:0)
//   BM_Neighbours    SPH neighbour build from scratch (cell grid)
//   BM_ContactPass   node-face contact: broad phase + 3 correction passes
//   BM_ImpactStep    full step of a projectile in a plate (~190k tets at the middle size),
//                    contact and erosion (mode 1) or FE -> SPH conversion (mode 2)
//   BM_FourPlates    full step of scenes/four_plates_normal (quick, default and fine resolutions)
// The full-step cases (BM_ImpactStep, BM_FourPlates) also report the run's figures of merit over
// the timed steps: element_phase_ns, particle_phase_ns and the conversion, contact and coupling
// phases' shares of the step (%).
#include "core/contact/node_face_contact.hpp"
#include "core/fem/element_forces.hpp"
#include "core/material/library.hpp"
#include "core/mesh/structured_box.hpp"
#include "core/scene/scene.hpp"
#include "core/solver/figures_of_merit.hpp"
#include "core/solver/phase_timers.hpp"
#include "core/solver/step.hpp"
#include "core/state/model_build.hpp"
#include "core/sph/particle_body.hpp"
#include "core/sph/sph_forces.hpp"

#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

using namespace fesph;

namespace {

const MaterialLibrary& library() {
  static const MaterialLibrary lib =
      MaterialLibrary::load(std::string(FESPH_SOURCE_DIR) + "/scenes/materials.toml");
  return lib;
}

void setThreads(benchmark::State& state, int arg) {
  omp_set_num_threads(static_cast<int>(state.range(arg)));
}

/// items per second and seconds per item (x 1e9 = ns per item), plus the item count.
void countItems(benchmark::State& state, const char* name, double items) {
  const double done = items * static_cast<double>(state.iterations());
  state.counters[name] = items;
  state.counters["items_per_s"] = benchmark::Counter(done, benchmark::Counter::kIsRate);
  state.counters["s_per_item"] = benchmark::Counter(
      done, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

/// The run's own figures of merit over the timed steps (reset the Model's timing before
/// them): ns per element-step in the element phase, per particle-step in the particle phase,
/// and each other phase's share of the step (%), so that a full-step case says where its time
/// went.
void countPhases(benchmark::State& state, const Model& m) {
  const PhaseTimes& t = m.timing;
  const auto seconds = [&](Phase p) { return t.seconds[static_cast<int>(p)]; };
  if (t.element_steps > 0)
    state.counters["element_phase_ns"] = 1e9 * seconds(Phase::Elements) / t.element_steps;
  if (t.particle_steps > 0)
    state.counters["particle_phase_ns"] = 1e9 * seconds(Phase::Particles) / t.particle_steps;
  const double total = t.total();
  if (total > 0)
    for (Phase p : {Phase::Conversion, Phase::Contact, Phase::Coupling, Phase::ParticleContact}) {
      std::string name = phaseName(p);
      std::replace(name.begin(), name.end(), ' ', '_');
      state.counters[name + "_pct"] = 100 * seconds(p) / total;
    }
}

/// Model arrays per element (B), for the <= 1 kB per element target.
void countMemory(benchmark::State& state, const Model& m) {
  const Footprint f = modelFootprint(m);
  if (!m.elems.conn.empty())
    state.counters["bytes_per_element"] =
        static_cast<double>(f.elements + f.nodes + f.contact) / static_cast<double>(m.elems.size());
  if (!m.particles.x.empty())
    state.counters["bytes_per_particle"] =
        static_cast<double>(f.particles) / static_cast<double>(m.particles.size());
}

// ---- memory bandwidth -------------------------------------------------------------------

void BM_Stream(benchmark::State& state) {
  setThreads(state, 0);
  const long n = 1L << 25;  // 3 arrays of 256 MB: far beyond every cache
  std::vector<double> a(n), b(n, 1.0), c(n, 2.0);
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i) a[i] = 0.0;  // first touch by the threads that use them
  const double s = 3.0;
  for (auto _ : state) {
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) a[i] = b[i] + s * c[i];
    benchmark::DoNotOptimize(a.data());
  }
  // 2 reads and 1 write; the write allocates its line too (4 transfers of 8 B)
  state.counters["bytes_per_s"] = benchmark::Counter(
      32.0 * static_cast<double>(n) * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate);
}

// ---- element kernel -----------------------------------------------------------------------

// An n^3-cell copper block (6 n^3 tets) in compression: every element takes the Johnson-Cook
// return path, with ANP, the Mie-Grueneisen EOS and bulk viscosity.
Model copperBlock(int n) {
  const Material mat = library().get("OFHC_copper");
  Model m;
  m.materials.push_back(mat);
  addBody(m, "block", structuredBox(Vec3::Zero(), Vec3(1e-2, 1e-2, 1e-2), n, n, n), 0,
          Placement{}, Vec3::Zero(), true);
  for (std::size_t a = 0; a < m.nodes.size(); ++a) {
    const Vec3 x = m.nodes.x0[a] - Vec3(5e-3, 5e-3, 5e-3);
    m.nodes.v[a] = Vec3(50 * x.x() / 5e-3, 50 * x.y() / 5e-3, -100 * x.z() / 5e-3);
  }
  finaliseModel(m);
  return m;
}

void BM_ElementKernel(benchmark::State& state) {
  setThreads(state, 1);
  Model m = copperBlock(static_cast<int>(state.range(0)));
  for (int i = 0; i < 5; ++i) step(m, 1.0);  // plastic flow under way
  const double dt = m.dt;
  for (auto _ : state) computeElementForces(m, dt);
  countItems(state, "elements", static_cast<double>(m.elems.size()));
  countMemory(state, m);
}

// ---- SPH ----------------------------------------------------------------------------------

// An n^3 lattice of copper particles (0.25 mm spacing), h = 1.2 spacing: ~55 neighbours
// inside. A uniform compression keeps the neighbour list in use across steps.
// shuffled: the particles in a random order (fixed seed) instead of the lattice's. Converted
// particles are numbered in the order their elements converted, far from spatial order.
// No renumbering (SphControls::order_interval = 0) unless the caller sets it. The cube moves
// with a uniform strain rate (1/s): negative squeezes it, positive stretches it into tension.
Model particleCube(int n, bool shuffled = false, double strain_rate = -2e4) {
  Model m;
  m.materials.push_back(library().get("OFHC_copper"));
  const double d = 0.25e-3;
  std::vector<Vec3> x;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) x.push_back(d * Vec3(i + 0.5, j + 0.5, k + 0.5));
  if (shuffled) std::shuffle(x.begin(), x.end(), std::mt19937(12345));
  addParticleBody(m, "cube", x, std::vector<double>(x.size(), d * d * d), 0, Vec3::Zero(),
                  true, 1.2);
  const Vec3 centre = 0.5 * n * d * Vec3::Ones();
  for (std::size_t i = 0; i < m.particles.size(); ++i)
    m.particles.v[i] = strain_rate * (m.particles.x[i] - centre);  // -2e4: 20 m/s at 1 mm
  m.sph.controls.order_interval = 0;
  return m;
}

double meanNeighbours(const Model& m) {
  return static_cast<double>(m.sph.neighbours.pairs()) / static_cast<double>(m.particles.size());
}

void BM_SphForces(benchmark::State& state) {
  setThreads(state, 2);
  const long order = state.range(1);
  Model m = particleCube(static_cast<int>(state.range(0)), order != 0);
  // order 2: renumbered at the start of step 5, and not again within the timed steps. Every
  // order times the same steps: the squeeze adds pairs from about step 57 on, and the pair
  // arrays' growth then faults in fresh pages (~1 s on this VM, docs/performance-history.md).
  if (order == 2) m.sph.controls.order_interval = 5;
  for (int i = 0; i < 6; ++i) step(m, 1.0);
  m.sph.controls.order_interval = 0;
  for (auto _ : state) step(m, 1.0);  // a particle step: forces, time step, integration
  countItems(state, "particles", static_cast<double>(m.particles.size()));
  state.counters["neighbours"] = meanNeighbours(m);
  countMemory(state, m);
}

// The cube stretched instead of squeezed: every particle inside in tension (p < 0), so every
// pair takes the artificial stress (a third of the impact's particles do, 2 % of the squeeze's)
// and none the viscosity.
void BM_SphTension(benchmark::State& state) {
  setThreads(state, 1);
  Model m = particleCube(static_cast<int>(state.range(0)), false, 2e4);
  for (int i = 0; i < 6; ++i) step(m, 1.0);
  for (auto _ : state) step(m, 1.0);
  countItems(state, "particles", static_cast<double>(m.particles.size()));
  state.counters["neighbours"] = meanNeighbours(m);
  std::size_t tensile = 0;
  for (const std::uint8_t t : m.sph.current.tensile) tensile += t ? 1 : 0;
  state.counters["tensile_fraction"] =
      static_cast<double>(tensile) / static_cast<double>(m.particles.size());
}

void BM_SphMirror(benchmark::State& state) {
  setThreads(state, 1);
  Model m = particleCube(static_cast<int>(state.range(0)));
  m.symmetry.push_back({1, 0.0});  // the face y = 0
  for (int i = 0; i < 5; ++i) step(m, 1.0);
  for (auto _ : state) step(m, 1.0);
  countItems(state, "particles", static_cast<double>(m.particles.size()));
  state.counters["neighbours"] = meanNeighbours(m);
  state.counters["mirror_pairs_per_particle"] =
      static_cast<double>(m.sph.mirrors.at(0).neighbours.pairs()) /
      static_cast<double>(m.particles.size());
}

void BM_Neighbours(benchmark::State& state) {
  setThreads(state, 1);
  Model m = particleCube(static_cast<int>(state.range(0)));
  NeighbourSearch search;
  NeighbourList list;
  for (auto _ : state) search.sphNeighbours(m.particles.x, m.particles.h, m.particles.body, list);
  countItems(state, "particles", static_cast<double>(m.particles.size()));
  state.counters["neighbours"] =
      static_cast<double>(list.pairs()) / static_cast<double>(m.particles.size());
}

// ---- contact and the full impact step -----------------------------------------------------

// A steel 1020 projectile (square section 10 mm, 20 mm long) at 1300 m/s, its nose 0.1 mm
// over an A36 plate (40 x 40 x 3.5 mm), both structured; n sets the cells per 10 mm.
// About 45 n^3 tets: n = 10: 46k, n = 16: 190k, n = 20: 365k.
Model impact(int n, ConversionMode mode) {
  Model m;
  m.materials.push_back(library().get("steel_1020"));
  m.materials.push_back(library().get("A36"));
  Placement proj, plate;
  proj.translation = Vec3(-5e-3, -5e-3, 0.1e-3);
  plate.translation = Vec3(-20e-3, -20e-3, -3.5e-3);
  const int nz_plate = std::max(2, static_cast<int>(0.35 * n + 0.5));
  addBody(m, "projectile", structuredBox(Vec3::Zero(), Vec3(10e-3, 10e-3, 20e-3), n, n, 2 * n),
          0, proj, Vec3(0, 0, -1300), true);
  addBody(m, "plate", structuredBox(Vec3::Zero(), Vec3(40e-3, 40e-3, 3.5e-3), 4 * n, 4 * n,
                                    nz_plate),
          1, plate, Vec3::Zero(), false);
  finaliseModel(m);
  m.controls.conversion.mode = mode;
  m.controls.conversion.plastic_strain = 0.3;
  return m;
}

void BM_ContactPass(benchmark::State& state) {
  setThreads(state, 1);
  Model m = impact(static_cast<int>(state.range(0)), ConversionMode::None);
  for (int i = 0; i < 20; ++i) step(m, 1.0);  // in contact
  const std::vector<Vec3> v = m.nodes.v;
  for (auto _ : state) {
    state.PauseTiming();
    m.nodes.v = v;
    state.ResumeTiming();
    enforceNodeFaceContact(m, m.dt, m.controls.contact);
  }
  countItems(state, "slaves", static_cast<double>(m.surfaces.candidates.slaves.size()));
}

void BM_ImpactStep(benchmark::State& state) {
  setThreads(state, 2);
  const ConversionMode mode =
      state.range(1) == 2 ? ConversionMode::Sph : ConversionMode::Erosion;
  Model m = impact(static_cast<int>(state.range(0)), mode);
  // 1.5 us into the impact: plastic flow, contact, conversions under way
  while (m.time < 1.5e-6) step(m, 1.0);
  m.timing = PhaseTimes{};
  const long builds = m.sph.search.verletBuilds();
  const long contact_builds = m.sph.search.contactVerletBuilds();
  for (auto _ : state) step(m, 1.0);
  countItems(state, "elements", static_cast<double>(m.elems.size()));
  state.counters["particles"] = static_cast<double>(m.particles.size());
  if (m.particles.size() > 0) {
    state.counters["neighbours"] = meanNeighbours(m);
    // Verlet list builds over the timed steps: SPH pairs, and particle-particle contact pairs
    state.counters["sph_builds"] = static_cast<double>(m.sph.search.verletBuilds() - builds);
    state.counters["contact_builds"] =
        static_cast<double>(m.sph.search.contactVerletBuilds() - contact_builds);
  }
  countMemory(state, m);
  countPhases(state, m);
}

// The four-plate scene meshed at a resolution preset, early in the impact on plate 1.
void BM_FourPlates(benchmark::State& state) {
  setThreads(state, 1);
  const char* const presets[] = {"quick", "default", "fine"};
  const char* preset = presets[state.range(0)];
  const Scene scene =
      loadScene(std::string(FESPH_SOURCE_DIR) + "/scenes/four_plates_normal/scene.toml",
                {std::string("resolution=\"") + preset + "\""});
  Model m = buildModel(scene);
  while (m.time < 2e-6) step(m, 1.0);  // the nose (1 mm out at 1300 m/s) 1.2 us into plate 1
  m.timing = PhaseTimes{};
  for (auto _ : state) step(m, 1.0);
  countItems(state, "elements", static_cast<double>(m.elems.size()));
  state.counters["particles"] = static_cast<double>(m.particles.size());
  countMemory(state, m);
  countPhases(state, m);
}

}  // namespace

BENCHMARK(BM_Stream)->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)
    ->UseRealTime();
// 6 n^3 tets: 6k, 48k, 197k
BENCHMARK(BM_ElementKernel)->ArgsProduct({{10, 20, 32}, {1, 2}})->ArgNames({"n", "threads"})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
// n^3 particles: 8k, 27k, 64k. A fixed 40 steps after the 6 of warm-up, before the squeeze adds
// pairs (about step 57): a longer run would time the pair arrays' growth and its page faults.
constexpr int kSphSteps = 40;
BENCHMARK(BM_SphForces)->ArgsProduct({{20, 30, 40}, {0, 1, 2}, {1, 2}})
    ->ArgNames({"n", "order", "threads"})->Iterations(kSphSteps)
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SphTension)->ArgsProduct({{20, 30, 40}, {1, 2}})->ArgNames({"n", "threads"})
    ->Iterations(kSphSteps)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SphMirror)->ArgsProduct({{20, 30, 40}, {1, 2}})->ArgNames({"n", "threads"})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Neighbours)->ArgsProduct({{20, 30, 40}, {1, 2}})->ArgNames({"n", "threads"})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ContactPass)->ArgsProduct({{10, 16, 20}, {1, 2}})->ArgNames({"n", "threads"})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
// The full-step cases time a fixed number of steps: their models change as they run (particles
// appear, contacts spread), so two builds or thread counts compare only over the same steps.
constexpr int kFullSteps = 10;
// mode 1: erosion (FE only), 2: FE -> SPH conversion
BENCHMARK(BM_ImpactStep)->ArgsProduct({{10, 16, 20}, {1, 2}, {1, 2}})
    ->ArgNames({"n", "mode", "threads"})->Iterations(kFullSteps)
    ->Unit(benchmark::kMillisecond)->UseRealTime();

// resolution 0: quick (22k tets), 1: default (186k), 2: fine (479k)
BENCHMARK(BM_FourPlates)->ArgsProduct({{0, 1, 2}, {1, 2}})->ArgNames({"resolution", "threads"})
    ->Iterations(kFullSteps)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
