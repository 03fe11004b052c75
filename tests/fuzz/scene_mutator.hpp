// SPDX-License-Identifier: MIT
// Random mutations of a scene text for the reader's fuzz test: byte flips, deleted,
// duplicated and swapped lines, swapped values, nasty values (huge, negative, non-finite,
// overflowing, of the wrong type), scaled numbers, truncation. Deterministic for a seed.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace fesph::testing {

namespace mutation {

inline std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

inline std::string join(const std::vector<std::string>& ls) {
  std::string s;
  for (const std::string& l : ls) s += l + '\n';
  return s;
}

// Values that break assumptions: huge, tiny, negative, non-finite, wrong type, overflow.
inline const char* const kNasty[] = {
    "1e308",  "1e400", "-1e308", "-1", "0", "-0.0", "nan", "inf", "-inf", "5e-324",
    "9223372036854775807", "-9223372036854775808", "99999999999999999999", "2147483648",
    "\"\"", "\"x\"", "[]", "[1e308, 1e308, 1e308]", "[nan, 0, 0]", "{}", "true", "1979-05-27",
    "[[]]", "\"../../../../etc/passwd\"", "[0, 0]", "[0, 0, 0, 0]", "3", "1e-30"};

}  // namespace mutation

class SceneMutator {
 public:
  explicit SceneMutator(std::uint64_t seed) : rng_(seed) {}

  std::string mutate(const std::string& text) {
    std::string s = text;
    const int ops = 1 + pick(3);
    for (int k = 0; k < ops; ++k) s = once(s);
    return s;
  }

 private:
  std::size_t pick(std::size_t n) { return n == 0 ? 0 : rng_() % n; }

  std::string once(const std::string& s) {
    std::vector<std::string> ls = mutation::lines(s);
    if (ls.empty() || s.empty()) return s + "x = 1\n";
    const std::size_t i = pick(ls.size()), j = pick(ls.size());
    switch (pick(9)) {
      case 0: {  // flip bytes
        std::string t = s;
        for (int n = 1 + static_cast<int>(pick(4)); n > 0; --n)
          t[pick(t.size())] = static_cast<char>(rng_() & 0xff);
        return t;
      }
      case 1: ls.erase(ls.begin() + static_cast<long>(i)); break;  // delete a line
      case 2: ls.insert(ls.begin() + static_cast<long>(i), ls[i]); break;  // duplicate it
      case 3: std::swap(ls[i], ls[j]); break;  // swap two lines
      case 4: {  // swap the values of two assignments
        const auto ei = ls[i].find('='), ej = ls[j].find('=');
        if (ei == std::string::npos || ej == std::string::npos) break;
        const std::string vi = ls[i].substr(ei + 1), vj = ls[j].substr(ej + 1);
        ls[i] = ls[i].substr(0, ei + 1) + vj;
        ls[j] = ls[j].substr(0, ej + 1) + vi;
        break;
      }
      case 5:
      case 6: {  // a nasty value in an assignment
        const auto e = ls[i].find('=');
        if (e == std::string::npos) break;
        ls[i] = ls[i].substr(0, e + 1) + " " + mutation::kNasty[pick(std::size(mutation::kNasty))];
        break;
      }
      case 7: return s.substr(0, pick(s.size()));  // truncate
      case 8: {  // a number scaled by a big or negative factor
        const auto e = ls[i].find('=');
        if (e == std::string::npos) break;
        const std::string v = ls[i].substr(e + 1);
        const double x = std::strtod(v.c_str(), nullptr);
        char buf[64];
        const int f = static_cast<int>(pick(3));
        std::snprintf(buf, sizeof buf, "%.17g", f == 0 ? -x : f == 1 ? x * 1e30 : x * 1e-30);
        ls[i] = ls[i].substr(0, e + 1) + " " + buf;
        break;
      }
    }
    return mutation::join(ls);
  }

  std::mt19937_64 rng_;
};


}  // namespace fesph::testing
