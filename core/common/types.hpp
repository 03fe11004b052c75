// SPDX-License-Identifier: MIT
// Small fixed-size types shared by every layer of the solver. SI units throughout.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>

namespace fesph {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

/// Symmetric 3x3 tensor stored as (xx, yy, zz, xy, yz, zx). Stresses in Pa, rates in 1/s.
struct Sym {
  double xx = 0, yy = 0, zz = 0, xy = 0, yz = 0, zx = 0;

  static Sym fromMatrix(const Mat3& a) {
    return {a(0, 0), a(1, 1), a(2, 2), 0.5 * (a(0, 1) + a(1, 0)), 0.5 * (a(1, 2) + a(2, 1)),
            0.5 * (a(2, 0) + a(0, 2))};
  }
  Mat3 matrix() const {
    Mat3 m;
    m << xx, xy, zx, xy, yy, yz, zx, yz, zz;
    return m;
  }
  double trace() const { return xx + yy + zz; }
  Sym deviator() const {
    const double m = trace() / 3.0;
    return {xx - m, yy - m, zz - m, xy, yz, zx};
  }
  /// Double contraction a:b.
  double dot(const Sym& b) const {
    return xx * b.xx + yy * b.yy + zz * b.zz + 2.0 * (xy * b.xy + yz * b.yz + zx * b.zx);
  }
  Sym operator+(const Sym& b) const {
    return {xx + b.xx, yy + b.yy, zz + b.zz, xy + b.xy, yz + b.yz, zx + b.zx};
  }
  Sym operator-(const Sym& b) const {
    return {xx - b.xx, yy - b.yy, zz - b.zz, xy - b.xy, yz - b.yz, zx - b.zx};
  }
  Sym operator*(double s) const { return {xx * s, yy * s, zz * s, xy * s, yz * s, zx * s}; }
  Sym& operator+=(const Sym& b) { return *this = *this + b; }
  Sym& operator*=(double s) { return *this = *this * s; }
};

/// Von Mises equivalent of a deviatoric tensor s: sqrt(3/2 s:s).
inline double vonMises(const Sym& s) { return std::sqrt(1.5 * s.dot(s)); }

}  // namespace fesph
