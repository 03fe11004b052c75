// SPDX-License-Identifier: MIT
#include "core/io/history_h5.hpp"

#include "core/common/error.hpp"
#include "core/io/run_metadata.hpp"
#include "core/state/model_build.hpp"

#include <array>
#include <cstring>

namespace fesph {

namespace {

constexpr std::size_t kLimiterSize = 32;  ///< bytes of a dt_limiter entry

enum class Kind { Real, Count, Text, Vector, Bodies };
struct ColumnSpec {
  const char* name;
  Kind kind;
  const char* units;
};

// The tables under /history, in the order record() appends to them.
const ColumnSpec kColumns[] = {
    {"time", Kind::Real, "s"},
    {"step", Kind::Count, ""},
    {"dt", Kind::Real, "s"},
    {"dt_limiter", Kind::Text, ""},
    {"kinetic", Kind::Real, "J"},
    {"internal", Kind::Real, "J"},
    {"plastic_work", Kind::Real, "J"},
    {"bulk_viscosity", Kind::Real, "J"},
    {"artificial_viscosity", Kind::Real, "J"},
    {"contact", Kind::Real, "J"},
    {"eroded", Kind::Real, "J"},
    {"conversion", Kind::Real, "J"},
    {"total", Kind::Real, "J"},
    {"balance_error", Kind::Real, "1"},
    {"momentum", Kind::Vector, "kg m/s"},
    {"projectile_velocity", Kind::Vector, "m/s"},
    {"body_velocity", Kind::Bodies, "m/s"},
    {"live_elements", Kind::Count, ""},
    {"eroded_elements", Kind::Count, ""},
    {"converted_elements", Kind::Count, ""},
    {"eroded_mass", Kind::Real, "kg"},
    {"particles", Kind::Count, ""},
};

int projectileBody(const Model& model) {
  for (std::size_t b = 0; b < model.bodies.size(); ++b)
    if (model.bodies[b].is_projectile) return static_cast<int>(b);
  return -1;
}

std::string bodyNames(const Model& model) {
  std::string names;
  for (const Body& b : model.bodies) names += (names.empty() ? "" : ",") + b.name;
  return names;
}

}  // namespace

HistoryH5::HistoryH5(const std::string& path, const Model& model, const std::string& scene_text)
    : file_(h5::openFile(path, h5::Mode::Create)), projectile_(projectileBody(model)) {
  writeRunMetadata(file_);
  h5::writeAttribute(file_, "format", std::string("fesph run"));
  h5::writeText(file_, "scene", scene_text);
  openTables(model, true, 0);
  h5::flush(file_);
}

HistoryH5::HistoryH5(const std::string& path, const Model& model, std::size_t rows)
    : file_(h5::openFile(path, h5::Mode::ReadWrite)), projectile_(projectileBody(model)) {
  if (!h5::hasAttribute(file_, "format") || h5::readStringAttribute(file_, "format") != "fesph run")
    throw RunError(path + ": not a fesph run file");
  openTables(model, false, rows);
  h5::flush(file_);
}

void HistoryH5::openTables(const Model& model, bool create, std::size_t rows) {
  const h5::Handle group =
      create ? h5::createGroup(file_, "history") : h5::openGroup(file_, "history");
  if (create) h5::writeAttribute(group, "bodies", bodyNames(model));
  const h5::Handle text = h5::stringType(kLimiterSize);
  for (const ColumnSpec& c : kColumns) {
    if (c.kind == Kind::Vector && std::strcmp(c.name, "projectile_velocity") == 0 &&
        projectile_ < 0)
      continue;
    hid_t type = H5T_NATIVE_DOUBLE;
    std::vector<hsize_t> shape;
    switch (c.kind) {
      case Kind::Real: break;
      case Kind::Count: type = H5T_NATIVE_INT64; break;
      case Kind::Text: type = text.id(); break;
      case Kind::Vector: shape = {3}; break;
      case Kind::Bodies: shape = {model.bodies.size(), 3}; break;
    }
    tables_.push_back(create ? h5::Table::create(group, c.name, type, shape, c.units)
                             : h5::Table::open(group, c.name, type, rows));
  }
  if (create && projectile_ >= 0) {
    h5::Handle set(H5Dopen2(group.id(), "projectile_velocity", H5P_DEFAULT));
    h5::writeAttribute(set, "body", model.bodies[projectile_].name);
  }
  rows_ = rows;
}

void HistoryH5::record(const Model& model) {
  const EnergyBudget& en = model.energy;
  const ConversionStats& cs = model.conversion;
  std::size_t k = 0;
  auto real = [&](double x) { tables_[k++].append(&x); };
  auto count = [&](long n) {
    const std::int64_t x = n;
    tables_[k++].append(&x);
  };
  auto vector = [&](const Vec3& v) { tables_[k++].append(v.data()); };

  real(en.time);
  count(en.step);
  real(model.dt);
  std::array<char, kLimiterSize> limiter{};
  std::strncpy(limiter.data(), model.dt_limiter.c_str(), kLimiterSize - 1);
  tables_[k++].append(limiter.data());
  for (double x : {en.kinetic, en.internal, en.plastic_work, en.bulk_viscosity,
                   en.artificial_viscosity, en.contact, en.eroded, en.conversion, en.total(),
                   en.balanceError()})
    real(x);
  vector(en.momentum);
  if (projectile_ >= 0) vector(bodyMeanVelocity(model, projectile_));
  std::vector<double> velocities;
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    const Vec3 v = bodyMeanVelocity(model, static_cast<int>(b));
    velocities.insert(velocities.end(), v.data(), v.data() + 3);
  }
  tables_[k++].append(velocities.data());
  count(static_cast<long>(model.elems.size()) - cs.eroded - cs.converted);
  count(cs.eroded);
  count(cs.converted);
  real(cs.eroded_mass);
  count(static_cast<long>(model.particles.size()));
  ++rows_;
  h5::flush(file_);
}

}  // namespace fesph
