// SPDX-License-Identifier: MIT
// The run's HDF5 file: metadata and extendible history tables that h5dump reads, and that a
// restart cuts back and continues.
#include "core/common/error.hpp"
#include "core/io/hdf5.hpp"
#include "core/io/history_csv.hpp"
#include "core/io/history_h5.hpp"
#include "core/io/run_metadata.hpp"
#include "core/scene/scene.hpp"
#include "core/solver/step.hpp"
#include "tests/support/temp_folder.hpp"
#include "tests/support/text.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
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
  // each row's step is its time's: the budget at t^n, which step n + 1 closes
  REQUIRE(column(h5dump("-d /history/step", file)) == std::vector<double>{0, 1, 2});
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
    REQUIRE(column(h5dump("-d /history/step", file)) == std::vector<double>{0, 1, 3});
  }
  SECTION("a file that is not a run file is refused") {
    const fs::path other = dir.path / "other.h5";
    std::ofstream(other) << "not hdf5";
    REQUIRE_THROWS_AS(HistoryH5(other.string(), model, 0), RunError);
  }
}

namespace {

// The values a history row must hold, taken from the model when the row is recorded; counts
// are counted here, not taken from the counters the writers read. The step is the one of the
// budget's time t^n: the step just taken (from t^n to t^(n+1)) closed it, so the model's less one.
struct Row {
  double time, dt, kinetic, internal, plastic_work, bulk_viscosity, artificial_viscosity,
      contact, eroded, conversion, total, balance_error, eroded_mass;
  Vec3 momentum;
  std::vector<Vec3> body_velocity;
  long step, live, eroded_elements, converted, particles;
  std::string limiter;
};

Row rowOf(const Model& m) {
  const EnergyBudget& e = m.energy;
  Row r{e.time, m.dt, e.kinetic, e.internal, e.plastic_work, e.bulk_viscosity,
        e.artificial_viscosity, e.contact, e.eroded, e.conversion,
        e.kinetic + e.internal + e.contact + e.eroded + e.conversion,
        std::abs(e.total() - e.initial) / e.initial, m.conversion.eroded_mass, e.momentum,
        {}, m.step - 1, 0, 0, 0, static_cast<long>(m.particles.size()), m.dt_limiter};
  for (std::size_t b = 0; b < m.bodies.size(); ++b)
    r.body_velocity.push_back(bodyMeanVelocity(m, static_cast<int>(b)));
  for (ElemStatus s : m.elems.status) {
    r.live += s == ElemStatus::Live;
    r.eroded_elements += s == ElemStatus::Eroded;
    r.converted += s == ElemStatus::Converted;
  }
  return r;
}

template <class T> std::vector<T> table(const h5::Handle& history, const std::string& name,
                                        std::size_t per_row, std::size_t rows) {
  std::vector<T> v(per_row * rows);
  h5::readArray(history, name, h5::nativeType<T>(), v.data());
  return v;
}

// Equal to the 10 significant digits history.csv prints.
bool printed(double csv, double x) { return std::abs(csv - x) <= 1e-9 * std::abs(x); }

}  // namespace

TEST_CASE("every history column, in run.h5 and history.csv, holds what its name says",
          "[unit][hdf5]") {
  // The restart scene with its bodies swapped, so that the projectile is not body 0: rows
  // after steps 30, 60 and 90 (the budgets of steps 29, 59 and 89), by which time elements
  // have turned into tied particles.
  const std::string path = std::string(FESPH_TEST_DATA_DIR) + "/restart_impact.toml";
  const std::string text = testing::slurp(path);
  const std::size_t b1 = text.find("[[bodies]]"), b2 = text.find("[[bodies]]", b1 + 1),
                    bc = text.find("[[boundary]]");
  REQUIRE(bc != std::string::npos);
  const std::string swapped = text.substr(0, b1) + text.substr(b2, bc - b2) +
                              text.substr(b1, b2 - b1) + text.substr(bc);
  const Scene scene =
      loadSceneText(swapped, path, {}, std::string(FESPH_SCENES_DIR) + "/materials.toml");
  REQUIRE(scene.bodies[1].projectile);
  Model model = buildModel(scene);
  testing::TempFolder dir("history_columns");
  const fs::path h5_path = dir.path / "run.h5", csv_path = dir.path / "history.csv";
  std::vector<Row> rows;
  {
    HistoryH5 h5(h5_path.string(), model, scene.text);
    HistoryCsv csv(csv_path.string(), model);
    while (model.step < 90) {
      step(model, scene.controls.end_time);
      if (model.step % 30 != 0) continue;
      REQUIRE(model.energy.time + model.dt == model.time);  // the budget is one step behind
      h5.record(model);
      csv.record(model);
      rows.push_back(rowOf(model));
    }
  }
  const Row& last = rows.back();
  REQUIRE(last.converted > 0);
  REQUIRE(last.particles > 0);
  REQUIRE(last.limiter.size() > 8);
  const std::size_t n = rows.size(), nb = model.bodies.size();

  SECTION("run.h5") {
    const h5::Handle file = h5::openFile(h5_path.string(), h5::Mode::Read);
    const h5::Handle history = h5::openGroup(file, "history");
    const std::pair<const char*, double Row::*> reals[] = {
        {"time", &Row::time}, {"dt", &Row::dt}, {"kinetic", &Row::kinetic},
        {"internal", &Row::internal}, {"plastic_work", &Row::plastic_work},
        {"bulk_viscosity", &Row::bulk_viscosity},
        {"artificial_viscosity", &Row::artificial_viscosity}, {"contact", &Row::contact},
        {"eroded", &Row::eroded}, {"conversion", &Row::conversion}, {"total", &Row::total},
        {"balance_error", &Row::balance_error}, {"eroded_mass", &Row::eroded_mass}};
    for (const auto& [name, field] : reals) {
      INFO(name);
      const std::vector<double> v = table<double>(history, name, 1, n);
      for (std::size_t k = 0; k < n; ++k) CHECK(v[k] == rows[k].*field);
    }
    const std::pair<const char*, long Row::*> counts[] = {
        {"step", &Row::step}, {"live_elements", &Row::live},
        {"eroded_elements", &Row::eroded_elements}, {"converted_elements", &Row::converted},
        {"particles", &Row::particles}};
    for (const auto& [name, field] : counts) {
      INFO(name);
      const std::vector<std::int64_t> v = table<std::int64_t>(history, name, 1, n);
      for (std::size_t k = 0; k < n; ++k) CHECK(v[k] == rows[k].*field);
    }
    const std::vector<double> momentum = table<double>(history, "momentum", 3, n);
    const std::vector<double> projectile = table<double>(history, "projectile_velocity", 3, n);
    const std::vector<double> bodies = table<double>(history, "body_velocity", 3 * nb, n);
    std::vector<char> limiter(32 * n);
    h5::readArray(history, "dt_limiter", h5::stringType(32).id(), limiter.data());
    for (std::size_t k = 0; k < n; ++k) {
      for (int c = 0; c < 3; ++c) {
        CHECK(momentum[3 * k + c] == rows[k].momentum[c]);
        CHECK(projectile[3 * k + c] == rows[k].body_velocity[1][c]);  // the projectile's
        for (std::size_t b = 0; b < nb; ++b)
          CHECK(bodies[3 * (nb * k + b) + c] == rows[k].body_velocity[b][c]);
      }
      CHECK(std::string(limiter.data() + 32 * k) == rows[k].limiter);
    }
    CHECK(h5::readStringAttribute(h5::openGroup(file, "history"), "bodies") == "plate,projectile");
    // each table's units
    const std::pair<const char*, const char*> units[] = {
        {"time", "s"}, {"dt", "s"}, {"kinetic", "J"}, {"internal", "J"}, {"plastic_work", "J"},
        {"bulk_viscosity", "J"}, {"artificial_viscosity", "J"}, {"contact", "J"},
        {"eroded", "J"}, {"conversion", "J"}, {"total", "J"}, {"balance_error", "1"},
        {"momentum", "kg m/s"}, {"projectile_velocity", "m/s"}, {"body_velocity", "m/s"},
        {"eroded_mass", "kg"}};
    for (const auto& [name, unit] : units) {
      INFO(name);
      const h5::Handle set(H5Dopen2(history.id(), name, H5P_DEFAULT));
      CHECK(h5::readStringAttribute(set, "units") == unit);
    }
  }

  SECTION("history.csv") {
    std::ifstream csv(csv_path);
    std::string line;
    REQUIRE(std::getline(csv, line));
    std::vector<std::string> header;
    for (std::stringstream h(line); std::getline(h, line, ',');) header.push_back(line);
    std::vector<std::vector<double>> values;
    while (std::getline(csv, line)) {
      values.emplace_back();
      for (std::stringstream r(line); std::getline(r, line, ',');)
        values.back().push_back(std::stod(line));
      REQUIRE(values.back().size() == header.size());
    }
    REQUIRE(values.size() == n);
    const auto column = [&](const std::string& name) {
      const auto at = std::find(header.begin(), header.end(), name);
      REQUIRE(at != header.end());
      return static_cast<std::size_t>(at - header.begin());
    };
    for (std::size_t k = 0; k < n; ++k) {
      const Row& r = rows[k];
      const std::vector<double>& v = values[k];
      for (auto [name, x] : {std::pair<std::string, double>{"time", r.time}, {"dt", r.dt},
                             {"kinetic", r.kinetic}, {"internal", r.internal},
                             {"plastic_work", r.plastic_work},
                             {"bulk_viscosity", r.bulk_viscosity}, {"contact", r.contact},
                             {"eroded", r.eroded}, {"conversion", r.conversion},
                             {"total", r.total}, {"balance_error", r.balance_error},
                             {"momentum_x", r.momentum.x()}, {"momentum_y", r.momentum.y()},
                             {"momentum_z", r.momentum.z()}, {"eroded_mass", r.eroded_mass}}) {
        INFO(name << " row " << k);
        CHECK(printed(v[column(name)], x));
      }
      CHECK(v[column("step")] == r.step);
      CHECK(v[column("eroded_elements")] == r.eroded_elements);
      CHECK(v[column("converted_elements")] == r.converted);
      CHECK(v[column("particles")] == r.particles);
      for (std::size_t b = 0; b < nb; ++b)
        for (int c = 0; c < 3; ++c) {
          const std::string name = model.bodies[b].name + "_v" + "xyz"[c];
          INFO(name << " row " << k);
          CHECK(printed(v[column(name)], r.body_velocity[b][c]));
        }
    }
  }
}
