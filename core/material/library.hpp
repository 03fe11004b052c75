// SPDX-License-Identifier: MIT
// The material library (scenes/materials.toml): named, sourced material constants, and the
// reader of one material table that scenes also use to override a few keys of a library entry.
#pragma once

#include "core/common/toml_check.hpp"
#include "core/material/material.hpp"

#include <map>
#include <string>
#include <vector>

namespace fesph {

/// Materials by id, read from a TOML file whose top-level tables are the materials.
class MaterialLibrary {
 public:
  /// Read and check every material of `path`; throws InputError (file:line:col).
  static MaterialLibrary load(const std::string& path);

  bool contains(const std::string& id) const;
  /// Throws std::out_of_range naming the unknown id.
  const Material& get(const std::string& id) const;
  /// All ids, sorted.
  std::vector<std::string> ids() const;

 private:
  std::map<std::string, Material> materials_;
};

/// Read one material table of the library schema over `base` (so a scene can override a
/// few keys of a library material), then finaliseMaterial; errors located in `file`.
/// A key may be left out when `base` already has a value for it: every key when `base` is a
/// finalised material, the keys of a sub-table ([johnson_cook], [damage], Mie-Grueneisen [eos])
/// when `base` already uses that model. `id` names the material in messages and is the
/// default name.
Material parseMaterial(const toml::table& t, const std::string& file, Material base,
                       const std::string& id);

}  // namespace fesph
