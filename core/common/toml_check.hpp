// SPDX-License-Identifier: MIT
// Strict reading of TOML tables (scenes, material library): every key must be known, every
// value of the expected type and range, and every error names file, line and column.
#pragma once

#include "core/common/error.hpp"
#include "core/common/types.hpp"

#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

namespace fesph::tomlcheck {

/// Parse a TOML document; syntax errors become InputError with the location toml++ reports.
toml::table parseFile(const std::string& path);
toml::table parseText(std::string_view text, const std::string& source_name);

/// Throw InputError located at `where` in `file`.
[[noreturn]] void fail(const std::string& file, const toml::source_region& where,
                       const std::string& message);

/// Reject any key of `t` that is not in `allowed`, suggesting the closest allowed key.
void allowKeys(const toml::table& t, const std::string& file,
               std::initializer_list<std::string_view> allowed, std::string_view context);
void allowKeys(const toml::table& t, const std::string& file,
               const std::vector<std::string>& allowed, std::string_view context);

/// The value of a number node (integer or float) as a double; NaN for any other node.
double numberValue(const toml::node& n);

/// Typed access. A missing key without a fallback is an error located at the table.
double number(const toml::table& t, std::string_view key, const std::string& file,
              std::optional<double> fallback = std::nullopt);
/// A number that must be > 0 (or >= 0 when `allow_zero`).
double positive(const toml::table& t, std::string_view key, const std::string& file,
                std::optional<double> fallback = std::nullopt, bool allow_zero = false);
long integer(const toml::table& t, std::string_view key, const std::string& file,
             std::optional<long> fallback = std::nullopt);
bool boolean(const toml::table& t, std::string_view key, const std::string& file,
             std::optional<bool> fallback = std::nullopt);
std::string string(const toml::table& t, std::string_view key, const std::string& file,
                   std::optional<std::string> fallback = std::nullopt);
/// A string that must be one of `choices`.
std::string choice(const toml::table& t, std::string_view key, const std::string& file,
                   std::initializer_list<std::string_view> choices,
                   std::optional<std::string> fallback = std::nullopt);
Vec3 vec3(const toml::table& t, std::string_view key, const std::string& file,
          std::optional<Vec3> fallback = std::nullopt);
std::vector<std::string> strings(const toml::table& t, std::string_view key,
                                 const std::string& file);
/// A sub-table; nullptr when absent and not `required`.
const toml::table* table(const toml::table& t, std::string_view key, const std::string& file,
                         bool required = false);
/// An array of tables (`[[key]]`); empty when absent.
std::vector<const toml::table*> tables(const toml::table& t, std::string_view key,
                                       const std::string& file);

/// Location of the value stored under `key` (or of the table when absent).
toml::source_region where(const toml::table& t, std::string_view key);

}  // namespace fesph::tomlcheck
