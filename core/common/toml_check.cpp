// SPDX-License-Identifier: MIT
#include "core/common/toml_check.hpp"

#include "core/common/read_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace fesph::tomlcheck {

namespace {

std::string typeName(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    default: return "a date/time";
  }
}

// Levenshtein distance, to suggest the key a typo was meant to be.
std::size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

template <class List>
void allowKeysImpl(const toml::table& t, const std::string& file, const List& allowed,
                   std::string_view context) {
  for (auto&& [k, v] : t) {
    (void)v;
    const std::string_view key = k.str();
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    // A suggestion within about a third of the key's letters (two for end_tiem): further
    // off, 'rho0' became "did you mean 'eos'?" and 'n' "'name'?", so the keys are listed.
    std::string best;
    const std::size_t reach =
        std::min<std::size_t>(3, std::max<std::size_t>(1, (key.size() + 1) / 3));
    std::size_t best_d = reach + 1;
    std::string all;
    for (const auto& a : allowed) {
      const std::size_t d = editDistance(key, a);
      if (d < best_d) best_d = d, best = std::string(a);
      all += (all.empty() ? "" : ", ") + std::string(a);
    }
    std::string msg = "unknown key '" + std::string(key) + "' in " + std::string(context);
    msg += best.empty() ? "; expected one of: " + all : "; did you mean '" + best + "'?";
    fail(file, k.source(), msg);
  }
}

const toml::node* find(const toml::table& t, std::string_view key) { return t.get(key); }

[[noreturn]] void missing(const toml::table& t, std::string_view key, const std::string& file,
                          const std::string& expected) {
  fail(file, t.source(), "missing key '" + std::string(key) + "': expected " + expected);
}

// A number for a message as a reader would write it: std::to_string prints 1e-9 as 0.000000.
std::string shortNumber(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

}  // namespace

toml::table parseText(std::string_view text, const std::string& source_name) {
  try {
    return toml::parse(text, std::string_view(source_name));
  } catch (const toml::parse_error& e) {
    throw InputError(source_name, static_cast<int>(e.source().begin.line),
                     static_cast<int>(e.source().begin.column),
                     "TOML syntax: " + std::string(e.description()));
  }
}

toml::table parseFile(const std::string& path) {
  std::string text, why;
  if (!readWholeFile(path, text, why)) throw InputError(path, 0, 0, "cannot read: " + why);
  return parseText(text, path);
}

void fail(const std::string& file, const toml::source_region& where, const std::string& msg) {
  throw InputError(file, static_cast<int>(where.begin.line), static_cast<int>(where.begin.column),
                   msg);
}

void allowKeys(const toml::table& t, const std::string& file,
               std::initializer_list<std::string_view> allowed, std::string_view context) {
  allowKeysImpl(t, file, allowed, context);
}

void allowKeys(const toml::table& t, const std::string& file,
               const std::vector<std::string>& allowed, std::string_view context) {
  allowKeysImpl(t, file, allowed, context);
}

toml::source_region where(const toml::table& t, std::string_view key) {
  const toml::node* n = find(t, key);
  return n ? n->source() : t.source();
}

double numberValue(const toml::node& n) {
  // toml++'s value<double>() is empty for an integer a double cannot hold exactly (2^63 - 1).
  if (const auto* i = n.as_integer()) return static_cast<double>(i->get());
  if (const auto* f = n.as_floating_point()) return f->get();
  return std::numeric_limits<double>::quiet_NaN();
}

double number(const toml::table& t, std::string_view key, const std::string& file,
              std::optional<double> fallback) {
  const toml::node* n = find(t, key);
  if (!n) {
    if (fallback) return *fallback;
    missing(t, key, file, "a number");
  }
  if (!n->is_number())
    fail(file, n->source(), "'" + std::string(key) + "' must be a number, not " + typeName(*n));
  const double x = numberValue(*n);
  if (!std::isfinite(x)) fail(file, n->source(), "'" + std::string(key) + "' must be finite");
  return x;
}

double positive(const toml::table& t, std::string_view key, const std::string& file,
                std::optional<double> fallback, bool allow_zero) {
  const double x = number(t, key, file, fallback);
  if (x < 0 || (!allow_zero && x == 0))
    fail(file, where(t, key),
         "'" + std::string(key) + "' must be " + (allow_zero ? ">= 0" : "> 0") + ", got " +
             shortNumber(x));
  return x;
}

long integer(const toml::table& t, std::string_view key, const std::string& file,
             std::optional<long> fallback) {
  const toml::node* n = find(t, key);
  if (!n) {
    if (fallback) return *fallback;
    missing(t, key, file, "an integer");
  }
  if (!n->is_integer())
    fail(file, n->source(), "'" + std::string(key) + "' must be an integer, not " + typeName(*n));
  return static_cast<long>(n->value<int64_t>().value());
}

bool boolean(const toml::table& t, std::string_view key, const std::string& file,
             std::optional<bool> fallback) {
  const toml::node* n = find(t, key);
  if (!n) {
    if (fallback) return *fallback;
    missing(t, key, file, "true or false");
  }
  if (!n->is_boolean())
    fail(file, n->source(), "'" + std::string(key) + "' must be true or false, not " + typeName(*n));
  return n->value<bool>().value();
}

std::string string(const toml::table& t, std::string_view key, const std::string& file,
                   std::optional<std::string> fallback) {
  const toml::node* n = find(t, key);
  if (!n) {
    if (fallback) return *fallback;
    missing(t, key, file, "a string");
  }
  if (!n->is_string())
    fail(file, n->source(), "'" + std::string(key) + "' must be a string, not " + typeName(*n));
  return n->value<std::string>().value();
}

std::string choice(const toml::table& t, std::string_view key, const std::string& file,
                   std::initializer_list<std::string_view> choices,
                   std::optional<std::string> fallback) {
  const std::string s = string(t, key, file, std::move(fallback));
  std::string all;
  for (auto c : choices) {
    if (c == s) return s;
    all += (all.empty() ? "\"" : ", \"") + std::string(c) + "\"";
  }
  fail(file, where(t, key), "'" + std::string(key) + "' = \"" + s + "\" is not one of " + all);
}

Vec3 vec3(const toml::table& t, std::string_view key, const std::string& file,
          std::optional<Vec3> fallback) {
  const toml::node* n = find(t, key);
  if (!n) {
    if (fallback) return *fallback;
    missing(t, key, file, "an array of 3 numbers");
  }
  const toml::array* a = n->as_array();
  if (!a || a->size() != 3)
    fail(file, n->source(), "'" + std::string(key) + "' must be an array of 3 numbers");
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    const toml::node& e = *a->get(static_cast<std::size_t>(i));
    if (!e.is_number() || !std::isfinite(numberValue(e)))
      fail(file, e.source(), "'" + std::string(key) + "' must hold 3 finite numbers");
    v[i] = numberValue(e);
  }
  return v;
}

std::vector<std::string> strings(const toml::table& t, std::string_view key,
                                 const std::string& file) {
  std::vector<std::string> out;
  const toml::node* n = find(t, key);
  if (!n) return out;
  const toml::array* a = n->as_array();
  if (!a) fail(file, n->source(), "'" + std::string(key) + "' must be an array of strings");
  for (const toml::node& e : *a) {
    if (!e.is_string()) fail(file, e.source(), "'" + std::string(key) + "' must hold strings");
    out.push_back(e.value<std::string>().value());
  }
  return out;
}

const toml::table* table(const toml::table& t, std::string_view key, const std::string& file,
                         bool required) {
  const toml::node* n = find(t, key);
  if (!n) {
    if (required) missing(t, key, file, "a table [" + std::string(key) + "]");
    return nullptr;
  }
  if (!n->is_table())
    fail(file, n->source(), "'" + std::string(key) + "' must be a table, not " + typeName(*n));
  return n->as_table();
}

std::vector<const toml::table*> tables(const toml::table& t, std::string_view key,
                                       const std::string& file) {
  std::vector<const toml::table*> out;
  const toml::node* n = find(t, key);
  if (!n) return out;
  const toml::array* a = n->as_array();
  if (!a)
    fail(file, n->source(), "'" + std::string(key) + "' must be an array of tables [[" +
                                std::string(key) + "]]");
  for (const toml::node& e : *a) {
    if (!e.is_table()) fail(file, e.source(), "'" + std::string(key) + "' must hold tables");
    out.push_back(e.as_table());
  }
  return out;
}

}  // namespace fesph::tomlcheck
