// SPDX-License-Identifier: MIT
// Cubic B-spline smoothing kernel in 3-D (Monaghan & Lattanzio 1985), support 2h, and its
// gradient. The one kernel of the SPH layer.
#pragma once

#include "core/common/types.hpp"

namespace fesph {

/// pi as a double: EIGEN_PI is a long double, which put every kernel evaluation on the x87 unit.
constexpr double kKernelPi = 3.14159265358979323846;

/// The kernel's shape without its normalisation: W(r, h) = kernelShape(r/h) / (pi h^3).
/// T is double, or two doubles side by side (Lanes2: the artificial stress takes two pairs at a
/// time, sph_forces.cpp) evaluated lane by lane with the same arithmetic, so the same bits:
/// both pieces are computed and one is selected.
template <class T>
inline T kernelShape(T q) {
  const T t = 2.0 - q;
  const T inner = 1.0 - 1.5 * q * q + 0.75 * q * q * q;
  const T outer = 0.25 * t * t * t;
  return q < 1.0 ? inner : q < 2.0 ? outer : T{};
}

/// W(r, h) = 1/(pi h^3) {1 - 1.5 q^2 + 0.75 q^3 (q < 1); 0.25 (2 - q)^3 (1 <= q < 2); 0},
/// q = r/h; r, h in m, W in 1/m^3. Integrates to 1 over space.
inline double kernelW(double r, double h) {
  return kernelShape(r / h) / (kKernelPi * h * h * h);
}

/// dW/dr divided by r (1/m^5): the gradient is this factor times the separation vector, and
/// the division is exact at r = 0 (the limit is -3/(pi h^5)), so no special case is needed.
/// T is double, or two doubles side by side (Lanes2) evaluated lane by lane with the same
/// arithmetic, so the same bits: both pieces are computed and one is selected (the outer
/// piece's 0/0 at r = 0 never is).
template <class T>
inline T kernelDWdrOverR(T r, T h) {
  const T q = r / h;
  const T norm = 1.0 / (kKernelPi * h * h * h * h * h);
  const T t = 2.0 - q;
  const T inner = norm * (-3.0 + 2.25 * q);
  const T outer = -norm * 0.75 * t * t / q;
  return q < 1.0 ? inner : q < 2.0 ? outer : T{};
}

/// grad_i W(|x_i - x_j|, h) for r_ij = x_i - x_j (1/m^4). Odd: grad W_ji = -grad W_ij.
inline Vec3 kernelGradient(const Vec3& r_ij, double h) {
  return kernelDWdrOverR(r_ij.norm(), h) * r_ij;
}

}  // namespace fesph
