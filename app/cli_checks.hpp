// SPDX-License-Identifier: MIT
// Command-line checks whose messages say what was expected: CLI11's PositiveNumber answers
// "abc" and -1 alike with a range that ends at the largest double, written out in 309 digits.
#pragma once

#include <CLI/CLI.hpp>

#include <cmath>
#include <string>
#include <type_traits>

namespace fesph {

/// `text` read whole as a number into `value` (a double, or a whole number into a long);
/// false when it is not one (or has more after it).
template <class T> bool readNumber(const std::string& text, T& value) {
  static_assert(std::is_same_v<T, double> || std::is_same_v<T, long>);
  std::size_t used = 0;
  try {
    if constexpr (std::is_same_v<T, long>)
      value = std::stol(text, &used);
    else
      value = std::stod(text, &used);
  } catch (const std::exception&) {
    return false;
  }
  return used == text.size();
}

/// A finite number above 0 (or at 0 too: `zero_allowed`).
inline CLI::Validator finiteNumber(bool zero_allowed) {
  const std::string expected = zero_allowed ? "a number >= 0" : "a number > 0";
  return CLI::Validator(
      [zero_allowed, expected](std::string& text) -> std::string {
        double value = 0;
        if (!readNumber(text, value)) return "expected a number, got '" + text + "'";
        if (!std::isfinite(value) || value < 0 || (value == 0 && !zero_allowed))
          return "expected " + expected + ", got " + text;
        return "";
      },
      zero_allowed ? "NUMBER >= 0" : "NUMBER > 0");
}

/// A number strictly between 0 and 1 (a brightness threshold).
inline CLI::Validator openFraction() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double value = 0;
        if (!readNumber(text, value) || !(value > 0 && value < 1))
          return "expected a number in (0, 1), got " + text;
        return "";
      },
      "NUMBER in (0, 1)");
}

/// A whole number from `lo` to `hi` (a thread count). CLI11's Range said "Value abc not in
/// range 1 to 1024" of a word that is no number at all.
inline CLI::Validator wholeNumber(int lo, int hi) {
  const std::string expected =
      "a whole number from " + std::to_string(lo) + " to " + std::to_string(hi);
  return CLI::Validator(
      [lo, hi, expected](std::string& text) -> std::string {
        long value = 0;
        if (!readNumber(text, value) || value < lo || value > hi)
          return "expected " + expected + ", got '" + text + "'";
        return "";
      },
      "INT in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

/// A time in s, a scale: a finite number > 0.
inline CLI::Validator positiveNumber() { return finiteNumber(false); }

/// A time in s that may be the start: a finite number >= 0.
inline CLI::Validator nonNegativeNumber() { return finiteNumber(true); }

}  // namespace fesph
