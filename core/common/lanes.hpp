// SPDX-License-Identifier: MIT
// Two doubles side by side, and the sum of 3x3 outer products that the SPH kinematics
// builds with them. The project is built for the baseline x86-64 (SSE2) and Eigen without
// vectorisation, so these are where two values share an instruction.
#pragma once

#include "core/common/types.hpp"

namespace fesph {

/// Two doubles side by side (a GCC vector: one SSE2 register on x86-64): +, -, *, / and
/// comparisons act lane by lane with the scalar operations' bits.
using Lanes2 = double __attribute__((vector_size(16)));

/// A sum of outer products u g^T, entry by entry as Mat3's `M.noalias() += u * g.transpose()`
/// computes it (M(a,b) + u_a g_b, the terms in the order given), so the same bits; rows 0 and 1
/// of each column side by side, two entries per instruction. Two such sums fit the registers
/// where two Mat3 (18 accumulators) did not.
struct OuterSum {
  Lanes2 top[3] = {};    ///< M(0, b) and M(1, b)
  double bottom[3] = {};  ///< M(2, b)
  void add(const Vec3& u, const Vec3& g) {
    const Lanes2 u01 = {u.x(), u.y()};
    for (int b = 0; b < 3; ++b) {
      top[b] += u01 * g[b];
      bottom[b] += u.z() * g[b];
    }
  }
  void subtract(const Vec3& u, const Vec3& g) {
    const Lanes2 u01 = {u.x(), u.y()};
    for (int b = 0; b < 3; ++b) {
      top[b] -= u01 * g[b];
      bottom[b] -= u.z() * g[b];
    }
  }
  Mat3 matrix() const {
    Mat3 m;
    for (int b = 0; b < 3; ++b) m.col(b) = Vec3(top[b][0], top[b][1], bottom[b]);
    return m;
  }
};

}  // namespace fesph
