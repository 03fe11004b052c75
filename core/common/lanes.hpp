// SPDX-License-Identifier: MIT
// Two doubles side by side, and the 3x3 products of the SPH passes built with them: the sum of
// outer products of the kinematics and the pair stress term of the forces. The project is
// built for the baseline x86-64 (SSE2) and Eigen without vectorisation, so these are where two
// values share an instruction (and the element pass's four-element lanes, element_forces.cpp,
// cloned for AVX).
#pragma once

#include "core/common/types.hpp"

#include <cmath>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace fesph {

/// Two doubles side by side (a GCC vector: one SSE2 register on x86-64): +, -, *, / and
/// comparisons act lane by lane with the scalar operations' bits.
using Lanes2 = double __attribute__((vector_size(16)));

/// The two lanes' square roots, in one instruction (sqrtpd) on x86-64: IEEE 754 rounds a square
/// root correctly, so each lane is std::sqrt's value bit for bit.
inline Lanes2 sqrtLanes(Lanes2 x) {
#ifdef __SSE2__
  return _mm_sqrt_pd(x);
#else
  return Lanes2{std::sqrt(x[0]), std::sqrt(x[1])};
#endif
}

/// The lengths of two vectors: Eigen's norm() of each, bit for bit (its squared norm, then the
/// root), with one root instruction for both.
inline Lanes2 norms(const Vec3& a, const Vec3& b) {
  return sqrtLanes(Lanes2{a.squaredNorm(), b.squaredNorm()});
}

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

/// c ((A + B) g) with the bits of Eigen's `c * ((A + B) * g)`: the scalar taken into the
/// matrix, each row's terms summed t0 + (t1 + t2); rows 0 and 1 side by side. Inline, where
/// GCC made Eigen's expression an out-of-line call in the SPH force pass (48 instructions a
/// call, and its arguments through memory).
inline Vec3 scaledSumTimes(double c, const Mat3& A, const Mat3& B, const Vec3& g) {
  Lanes2 top[3];
  double bottom[3];
  for (int b = 0; b < 3; ++b) {
    const Lanes2 a01 = {A(0, b), A(1, b)}, b01 = {B(0, b), B(1, b)};
    top[b] = (c * (a01 + b01)) * g[b];
    bottom[b] = (c * (A(2, b) + B(2, b))) * g[b];
  }
  const Lanes2 t01 = top[0] + (top[1] + top[2]);
  return Vec3(t01[0], t01[1], bottom[0] + (bottom[1] + bottom[2]));
}

}  // namespace fesph
