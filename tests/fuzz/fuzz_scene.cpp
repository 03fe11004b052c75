// SPDX-License-Identifier: MIT
// Fuzz test of the scene reader, built with AddressSanitizer and UBSan (tests/CMakeLists.txt):
// random mutations of the reference scenes (scenes/*/scene.toml) must give a scene or an
// InputError that names the file and a line, never a crash, another exception or a hang.
// Deterministic: a fixed seed; a failing case is written out to reproduce it.
//   fesph_fuzz_scene [MUTATIONS_PER_SCENE] [SEED]
#include "core/common/error.hpp"
#include "core/scene/scene.hpp"
#include "tests/fuzz/scene_mutator.hpp"

#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

using namespace fesph;
namespace fs = std::filesystem;

namespace {

std::string g_case;  // the text under test, written out if the process dies on it

void writeCase(const char* why) {
  const fs::path out = fs::temp_directory_path() / "fesph_fuzz_failure.toml";
  std::ofstream(out) << g_case;
  std::fprintf(stderr, "fuzz: %s; the scene is in %s\n", why, out.c_str());
}

extern "C" void onAlarm(int) {
  writeCase("the reader hangs (no answer within 10 s)");
  std::_Exit(3);
}

// A scene the reader accepted must hold only finite, sensible numbers.
std::string checkScene(const Scene& sc) {
  const SolverControls& c = sc.controls;
  if (!(c.end_time > 0 && std::isfinite(c.end_time))) return "end_time";
  if (!(c.courant > 0 && c.courant <= 1)) return "courant";
  if (!(sc.output.interval > 0 && std::isfinite(sc.output.interval))) return "output interval";
  if (sc.output.history_every < 1) return "history_every";
  if (sc.bodies.empty()) return "no bodies";
  for (const SceneBody& b : sc.bodies) {
    if (!b.velocity.allFinite()) return "body velocity";
    // Within the reader's limit of 50 million tetrahedra (8.5 V / h^3), with a margin for
    // its refinement-zone estimate.
    if (const auto* p = std::get_if<ProjectileSpec>(&b.shape))
      if (8.5 * p->diameter * p->diameter * p->length / std::pow(p->mesh_size, 3) > 2e8)
        return "projectile mesh size (too many elements)";
    if (const auto* p = std::get_if<PlateSpec>(&b.shape))
      if (8.5 * p->size_x * p->size_y * p->thickness / std::pow(p->coarse_size, 3) > 2e8)
        return "plate mesh size (too many elements)";
    if (!b.placement.translation.allFinite() || !b.placement.rotation.allFinite())
      return "body placement";
  }
  for (const Material& m : sc.materials)
    if (!(m.rho0 > 0 && std::isfinite(m.rho0) && m.E > 0 && std::isfinite(m.E)))
      return "material " + m.name;
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  const long per_scene = argc > 1 ? std::atol(argv[1]) : 1000;
  const std::uint64_t seed = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 20261201;
  const std::string scenes = FESPH_SCENES_DIR;
  const std::string library = scenes + "/materials.toml";
  std::signal(SIGALRM, onAlarm);

  std::vector<fs::path> references;
  for (const auto& d : fs::directory_iterator(scenes))
    if (fs::exists(d.path() / "scene.toml")) references.push_back(d.path() / "scene.toml");
  std::sort(references.begin(), references.end());
  if (references.empty()) {
    std::fprintf(stderr, "fuzz: no reference scenes in %s\n", scenes.c_str());
    return 1;
  }

  testing::SceneMutator mutator(seed);
  long valid = 0, located = 0, failures = 0;
  for (const fs::path& ref : references) {
    std::ifstream in(ref, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    // The reference itself must load.
    loadSceneText(text, ref.string(), {}, library);
    for (long k = 0; k < per_scene; ++k) {
      g_case = mutator.mutate(text);
      alarm(10);
      try {
        const Scene sc = loadSceneText(g_case, ref.string(), {}, library);
        const std::string bad = checkScene(sc);
        if (!bad.empty()) {
          ++failures;
          writeCase(("accepted a scene with a bad " + bad).c_str());
        }
        ++valid;
      } catch (const InputError& e) {
        if (e.file().empty() || e.line() <= 0) {
          ++failures;
          std::fprintf(stderr, "fuzz: error without a line: %s\n", e.what());
          writeCase("unlocated error");
        } else {
          ++located;
        }
      } catch (const std::exception& e) {
        ++failures;
        std::fprintf(stderr, "fuzz: %s escaped the reader: %s\n", typeid(e).name(), e.what());
        writeCase("not an InputError");
      }
      alarm(0);
    }
  }
  std::printf("fuzz: %zu reference scenes, %ld mutations: %ld valid scenes, %ld located errors, "
              "%ld failures (seed %llu)\n",
              references.size(), per_scene * static_cast<long>(references.size()), valid,
              located, failures, static_cast<unsigned long long>(seed));
  return failures == 0 ? 0 : 1;
}
