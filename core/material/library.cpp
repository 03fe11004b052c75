// SPDX-License-Identifier: MIT
// Strict reading of the material library schema (SI units; see docs/materials.md).
#include "core/material/library.hpp"

#include <optional>
#include <stdexcept>

namespace fesph {

namespace {

using tomlcheck::number;

/// The base value as fallback, or none (the key is required) when the base has no value.
std::optional<double> from(bool base_has_it, double value) {
  return base_has_it ? std::optional<double>(value) : std::nullopt;
}

std::optional<std::string> from(const std::string& value) {
  return value.empty() ? std::nullopt : std::optional<std::string>(value);
}

/// Where the value behind a finaliseMaterial key ("density", "eos.c0") sits in `t`: the
/// value itself when this table sets it, else the sub-table, else the material table.
toml::source_region locate(const toml::table& t, const std::string& key) {
  const auto dot = key.find('.');
  if (dot == std::string::npos) return tomlcheck::where(t, key);
  const toml::table* sub = t.get_as<toml::table>(key.substr(0, dot));
  return sub ? tomlcheck::where(*sub, key.substr(dot + 1)) : t.source();
}

Material readMaterial(const toml::table& t, const std::string& file, Material base,
                      const std::string& id) {
  const std::string ctx = "material '" + id + "'";
  tomlcheck::allowKeys(t, file,
                       {"name", "status", "source", "density", "youngs_modulus", "poisson_ratio",
                        "specific_heat", "room_temperature", "melt_temperature",
                        "taylor_quinney", "erosion_strain", "johnson_cook", "damage", "eos"},
                       ctx);
  // G is set by finaliseMaterial only: a base with G > 0 is a complete material.
  const bool full_base = base.G > 0;
  Material m = base;
  m.name = tomlcheck::string(t, "name", file, base.name.empty() ? id : base.name);
  m.status = tomlcheck::choice(t, "status", file, {"published", "stand-in", "assumption"},
                               from(base.status));
  m.source = tomlcheck::string(t, "source", file, from(base.source));
  m.rho0 = number(t, "density", file, from(full_base, base.rho0));
  m.E = number(t, "youngs_modulus", file, from(full_base, base.E));
  m.nu = number(t, "poisson_ratio", file, from(full_base, base.nu));
  // Optional even for a new material: no heating, 293 K, no thermal softening, chi 0.9, no erosion.
  m.cp = number(t, "specific_heat", file, base.cp);
  m.T_room = number(t, "room_temperature", file, base.T_room);
  m.T_melt = number(t, "melt_temperature", file, base.T_melt);
  m.taylor_quinney = number(t, "taylor_quinney", file, base.taylor_quinney);
  m.erosion_strain = number(t, "erosion_strain", file, base.erosion_strain);

  if (const toml::table* jc = tomlcheck::table(t, "johnson_cook", file)) {
    tomlcheck::allowKeys(*jc, file, {"A", "B", "n", "C", "m", "reference_rate"},
                         ctx + " [johnson_cook]");
    const bool had = base.strength == StrengthModel::JohnsonCook;
    m.strength = StrengthModel::JohnsonCook;
    m.A = number(*jc, "A", file, from(had, base.A));
    m.B = number(*jc, "B", file, from(had, base.B));
    m.n = number(*jc, "n", file, from(had, base.n));
    m.C = number(*jc, "C", file, from(had, base.C));
    m.m = number(*jc, "m", file, from(had, base.m));
    m.eps_dot0 = number(*jc, "reference_rate", file, base.eps_dot0);
  }
  if (const toml::table* d = tomlcheck::table(t, "damage", file)) {
    tomlcheck::allowKeys(*d, file, {"D1", "D2", "D3", "D4", "D5"}, ctx + " [damage]");
    const bool had = base.damage;
    m.damage = true;
    m.D1 = number(*d, "D1", file, from(had, base.D1));
    m.D2 = number(*d, "D2", file, from(had, base.D2));
    m.D3 = number(*d, "D3", file, from(had, base.D3));
    m.D4 = number(*d, "D4", file, from(had, base.D4));
    m.D5 = number(*d, "D5", file, from(had, base.D5));
  }
  if (const toml::table* e = tomlcheck::table(t, "eos", file)) {
    const bool had_mg = base.eos == EosModel::MieGruneisen;
    const std::string type = tomlcheck::choice(
        *e, "type", file, {"linear", "mie_gruneisen"},
        std::string(had_mg ? "mie_gruneisen" : "linear"));
    if (type == "linear") {
      // The linear EOS uses K from E and nu: c0, s, gamma0 would be silently ignored.
      tomlcheck::allowKeys(*e, file, {"type"}, ctx + " [eos] of type \"linear\"");
      m.eos = EosModel::Linear;
    } else {
      tomlcheck::allowKeys(*e, file, {"type", "c0", "s", "gamma0"}, ctx + " [eos]");
      m.eos = EosModel::MieGruneisen;
      m.c0 = number(*e, "c0", file, from(had_mg, base.c0));
      m.s = number(*e, "s", file, from(had_mg, base.s));
      m.gamma0 = number(*e, "gamma0", file, from(had_mg, base.gamma0));
    }
  }

  std::string key;
  const std::string problem = finaliseMaterial(m, key);
  if (!problem.empty()) tomlcheck::fail(file, locate(t, key), ctx + ": " + problem);
  return m;
}

}  // namespace

Material parseMaterial(const toml::table& t, const std::string& file, Material base,
                       const std::string& id) {
  // Every message names the material: a key missing from a table a --set made has no line.
  const std::string ctx = "material '" + id + "'";
  try {
    return readMaterial(t, file, std::move(base), id);
  } catch (const InputError& e) {
    if (e.message().find(ctx) != std::string::npos) throw;
    throw InputError(e.file(), e.line(), e.column(), ctx + ": " + e.message());
  }
}

MaterialLibrary MaterialLibrary::load(const std::string& path) {
  const toml::table root = tomlcheck::parseFile(path);
  MaterialLibrary lib;
  for (auto&& [k, v] : root) {
    const std::string id(k.str());
    const toml::table* t = v.as_table();
    if (!t)
      tomlcheck::fail(path, k.source(),
                      "'" + id + "' must be a material table [" + id + "], not a value");
    lib.materials_.emplace(id, parseMaterial(*t, path, Material{}, id));
  }
  if (lib.materials_.empty())
    throw InputError(path, 0, 0, "the material library defines no materials");
  return lib;
}

bool MaterialLibrary::contains(const std::string& id) const { return materials_.count(id) > 0; }

const Material& MaterialLibrary::get(const std::string& id) const {
  const auto it = materials_.find(id);
  if (it == materials_.end()) throw std::out_of_range("unknown material '" + id + "'");
  return it->second;
}

std::vector<std::string> MaterialLibrary::ids() const {
  std::vector<std::string> out;
  out.reserve(materials_.size());
  for (const auto& entry : materials_) out.push_back(entry.first);
  return out;
}

}  // namespace fesph
