// SPDX-License-Identifier: MIT
// Figures of merit of the solver loops (Google Benchmark; JSON with --benchmark_format=json):
// a full FE step (tet4 + elastic or Johnson-Cook + ANP + EOS + bulk viscosity + gather).
// Threads follow OMP_NUM_THREADS. Not a test: run `build/fesph_bench`.
#include "core/material/library.hpp"
#include "core/solver/step.hpp"
#include "tests/support/models.hpp"

#include <benchmark/benchmark.h>

using namespace fesph;

namespace {

// A block in compression: with OFHC copper every element takes the Johnson-Cook return path;
// with the elastic material, the linear elastic solver of the foundation.
Model block(int n, bool plastic) {
  const MaterialLibrary lib =
      MaterialLibrary::load(std::string(FESPH_SOURCE_DIR) + "/scenes/materials.toml");
  const Material mat = plastic ? lib.get("OFHC_copper") : fesph::testing::elasticMaterial();
  Model m = fesph::testing::boxModel(mat, Vec3(1e-2, 1e-2, 1e-2), n, n, n);
  for (std::size_t a = 0; a < m.nodes.size(); ++a) {
    const Vec3 x = m.nodes.x0[a] - Vec3(5e-3, 5e-3, 5e-3);
    m.nodes.v[a] = Vec3(50 * x.x() / 5e-3, 50 * x.y() / 5e-3, -100 * x.z() / 5e-3);
  }
  finaliseModel(m);
  return m;
}

void BM_FeStep(benchmark::State& state) {
  Model m = block(static_cast<int>(state.range(0)), state.range(1) != 0);
  for (int i = 0; i < 5; ++i) step(m, 1.0);  // warm up: plastic flow under way
  for (auto _ : state) step(m, 1.0);
  const double elements = static_cast<double>(m.elems.size());
  state.counters["elements"] = elements;
  state.counters["element_steps_per_s"] =
      benchmark::Counter(elements * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate);
  // seconds per element-step (shown in s; x 1e9 = ns per element-step)
  state.counters["s_per_element_step"] = benchmark::Counter(
      elements * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

}  // namespace

// 6 n^3 tets: 6k, 48k, 94k (the 100k-element figure), 197k; second argument: 1 plastic
// (Johnson-Cook copper), 0 elastic
BENCHMARK(BM_FeStep)
    ->ArgsProduct({{10, 20, 25, 32}, {0, 1}})
    ->ArgNames({"n", "plastic"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
