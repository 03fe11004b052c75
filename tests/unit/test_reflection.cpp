// SPDX-License-Identifier: MIT
// The mirror images of a model cut by symmetry planes: points, vectors and tensors.
#include "core/common/reflection.hpp"

#include <catch2/catch.hpp>

using namespace fesph;

TEST_CASE("mirror images reflect points, vectors and tensors as P x, P v, P T P",
          "[unit][symmetry]") {
  const std::vector<Reflection> half = mirrorImages({{1, 2e-3}});
  REQUIRE(half.size() == 1);
  const Vec3 x(1e-3, 5e-3, -3e-3), v(10, 20, 30);
  CHECK(half[0].point(x).isApprox(Vec3(1e-3, -1e-3, -3e-3), 1e-15));
  CHECK(half[0].vector(v) == Vec3(10, -20, 30));

  // A quarter model: three images, the planes alone and both together.
  const std::vector<Reflection> quarter = mirrorImages({{0, 0.0}, {2, 1e-3}});
  REQUIRE(quarter.size() == 3);
  CHECK(quarter[0].vector(v) == Vec3(-10, 20, 30));
  CHECK(quarter[1].vector(v) == Vec3(10, 20, -30));
  CHECK(quarter[2].vector(v) == Vec3(-10, 20, -30));
  CHECK(quarter[2].point(x).isApprox(Vec3(-1e-3, 5e-3, 5e-3), 1e-15));
  Mat3 T;
  T << 1, 2, 3, 4, 5, 6, 7, 8, 9;
  for (const Reflection& r : quarter) {
    Mat3 P = Mat3::Identity();
    for (int a = 0; a < 3; ++a)
      if (r.flip[a]) P(a, a) = -1;
    CHECK(r.tensor(T) == P * T * P);
    // a reflection is its own inverse
    CHECK(r.point(r.point(x)).isApprox(x, 1e-15));
  }
}
