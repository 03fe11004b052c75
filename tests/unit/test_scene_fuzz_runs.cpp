// SPDX-License-Identifier: MIT
// The fuzz test's other half (the reader's is tests/fuzz/fuzz_scene.cpp, under sanitizers):
// a handful of mutated Taylor scenes that the reader accepts are meshed and stepped. Each must
// run or stop with an InputError or RunError, never crash or throw anything else.
#include "core/common/error.hpp"
#include "core/scene/scene.hpp"
#include "core/solver/step.hpp"
#include "tests/fuzz/scene_mutator.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

using namespace fesph;

TEST_CASE("accepted mutations of a reference scene mesh and step or fail cleanly",
          "[unit][scene][fuzz]") {
  const std::string ref = std::string(FESPH_SCENES_DIR) + "/taylor_benchmark/scene.toml";
  const std::string library = std::string(FESPH_SCENES_DIR) + "/materials.toml";
  std::ifstream in(ref);
  std::stringstream ss;
  ss << in.rdbuf();
  testing::SceneMutator mutator(42);
  int meshed = 0, tried = 0;
  for (int k = 0; k < 2000 && meshed < 4; ++k) {
    const std::string text = mutator.mutate(ss.str());
    Scene scene;
    try {
      scene = loadSceneText(text, ref, {}, library);
    } catch (const InputError&) {
      continue;  // the reader's own fuzz test checks these
    }
    // Keep it fast: bars of at most a few thousand tetrahedra (8.5 V / h^3).
    const auto* bar = std::get_if<ProjectileSpec>(&scene.bodies[0].shape);
    if (!bar || 8.5 * bar->diameter * bar->diameter * bar->length / std::pow(bar->mesh_size, 3) >
                    2e4)
      continue;
    ++tried;
    INFO(text);
    try {
      Model model = buildModel(scene);
      for (int s = 0; s < 5 && model.time < model.controls.end_time; ++s)
        step(model, model.controls.end_time);
      ++meshed;
    } catch (const InputError&) {
    } catch (const RunError&) {
    }
  }
  REQUIRE(meshed >= 4);
  REQUIRE(tried >= meshed);
}
