// SPDX-License-Identifier: MIT
// The run's HDF5 file: metadata and extendible history tables that h5dump reads, and that a
// restart cuts back and continues.
#include "core/common/error.hpp"
#include "core/io/history_h5.hpp"
#include "core/io/run_metadata.hpp"
#include "core/scene/scene.hpp"
#include "core/solver/step.hpp"
#include "tests/support/temp_folder.hpp"

#include <catch2/catch.hpp>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

using namespace fesph;
namespace fs = std::filesystem;

namespace {

std::string h5dump(const std::string& args, const fs::path& file) {
  const fs::path out = file.string() + ".txt";
  const int status = std::system(("h5dump " + args + " " + file.string() + " > " +
                                  out.string() + " 2>&1").c_str());
  REQUIRE(WIFEXITED(status));
  REQUIRE(WEXITSTATUS(status) == 0);
  std::ifstream in(out);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The numbers h5dump prints in the DATA block of a 1D dataset.
std::vector<double> column(const std::string& dump) {
  std::vector<double> values;
  std::size_t at = dump.find("DATA {");
  REQUIRE(at != std::string::npos);
  at = dump.find('\n', at);
  std::istringstream in(dump.substr(at, dump.find('}', at) - at));
  std::string token;
  while (in >> token) {
    if (token.back() == ',') token.pop_back();
    if (token.find(':') != std::string::npos) continue;  // "(0):" index labels
    values.push_back(std::stod(token));
  }
  return values;
}

}  // namespace

TEST_CASE("run.h5 holds the metadata and a history table per quantity, read by h5dump",
          "[unit][hdf5]") {
  testing::TempFolder dir("history_h5");
  const Scene scene = loadScene(std::string(FESPH_TEST_DATA_DIR) + "/restart_impact.toml", {},
                                std::string(FESPH_SCENES_DIR) + "/materials.toml");
  Model model = buildModel(scene);
  const fs::path file = dir.path / "run.h5";
  std::vector<double> times;
  {
    HistoryH5 h5(file.string(), model, scene.text);
    for (int row = 0; row < 3; ++row) {
      step(model, scene.controls.end_time);
      h5.record(model);
      times.push_back(model.energy.time);
    }
    REQUIRE(h5.rows() == 3);
  }
  // Values as written (h5dump prints 17 significant digits of a double: exact round trip).
  REQUIRE(column(h5dump("-m %.17g -d /history/time", file)) == times);
  REQUIRE(column(h5dump("-d /history/step", file)) == std::vector<double>{1, 2, 3});
  const std::string header = h5dump("-H", file);
  for (const char* name : {"kinetic", "internal", "plastic_work", "contact", "eroded",
                           "conversion", "balance_error", "momentum", "projectile_velocity",
                           "body_velocity", "live_elements", "converted_elements",
                           "particles", "dt", "dt_limiter"})
    REQUIRE(header.find(std::string("DATASET \"") + name + "\"") != std::string::npos);
  REQUIRE(header.find("H5S_UNLIMITED") != std::string::npos);  // extendible
  const std::string meta = h5dump("-a /git_hash -a /fesph_version -a /units -d /scene", file);
  REQUIRE(meta.find(gitHash()) != std::string::npos);
  REQUIRE(meta.find(FESPH_VERSION) != std::string::npos);
  REQUIRE(meta.find("SI") != std::string::npos);
  REQUIRE(meta.find("Restart test: small impact") != std::string::npos);  // the scene text
  const std::string units = h5dump("-a /history/kinetic/units", file);
  REQUIRE(units.find("\"J\"") != std::string::npos);

  SECTION("a restart cuts the tables back to the checkpoint's rows and appends") {
    {
      HistoryH5 h5(file.string(), model, 2);
      REQUIRE(h5.rows() == 2);
      step(model, scene.controls.end_time);
      h5.record(model);
    }
    const std::vector<double> t = column(h5dump("-m %.17g -d /history/time", file));
    REQUIRE(t == std::vector<double>{times[0], times[1], model.energy.time});
    REQUIRE(column(h5dump("-d /history/step", file)) == std::vector<double>{1, 2, 4});
  }
  SECTION("a file that is not a run file is refused") {
    const fs::path other = dir.path / "other.h5";
    std::ofstream(other) << "not hdf5";
    REQUIRE_THROWS_AS(HistoryH5(other.string(), model, 0), RunError);
  }
}
