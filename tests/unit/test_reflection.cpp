// SPDX-License-Identifier: MIT
// The mirror images of a model cut by symmetry planes (points, vectors and tensors), and the
// particles kept on their side of a plane.
#include "core/common/reflection.hpp"
#include "core/solver/boundary.hpp"
#include "core/sph/sph_forces.hpp"

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

TEST_CASE("particles stop a tenth of a spacing off a symmetry plane, on their own side",
          "[unit][symmetry]") {
  Model m;
  m.symmetry.push_back({1, 1e-3});  // the plane y = 1 mm
  Particles& pa = m.particles;
  const double V = 1e-9, dt = 1e-6;  // spacing 1 mm, so 0.1 mm off the plane
  // heading for the plane from above and below; born closer than a quarter spacing and
  // heading in; leaving the plane
  pa.x = {Vec3(0, 2e-3, 0), Vec3(0, -1e-3, 0), Vec3(0, 1.05e-3, 0), Vec3(0, 1.5e-3, 0)};
  pa.v = {Vec3(5, -1000, 7), Vec3(0, 3000, 0), Vec3(0, -50, 0), Vec3(0, 100, 0)};
  pa.V.assign(4, V);
  enforceSymmetryPlanes(m, dt);
  CHECK(pa.v[0].y() == Approx(-900));  // ends at 1.1 mm
  CHECK(pa.v[0].x() == 5);             // the tangential velocity is free
  CHECK(pa.v[0].z() == 7);
  CHECK(pa.v[1].y() == Approx(1900));  // ends at 0.9 mm
  CHECK(pa.v[2].y() == 0);             // kept from coming closer
  CHECK(pa.v[3].y() == 100);
}

TEST_CASE("a particle between another body's particle and its mirror image is stopped by both",
          "[unit][symmetry]") {
  // A sits 0.1 mm off the plane y = 0; B, of another body, comes at it along -x, 0.3 mm off
  // the plane: in the full model B's image comes at it too, 0.72 mm away (spacings of 1 mm).
  Model m;
  m.symmetry.push_back({1, 0.0});
  Particles& pa = m.particles;
  pa.x = {Vec3(0, 0.1e-3, 0), Vec3(0.6e-3, 0.3e-3, 0)};
  pa.v = {Vec3::Zero(), Vec3(-300, 0, 0)};
  pa.m = {7.8e-6, 7.8e-6};
  pa.V = {1e-9, 1e-9};
  pa.body = {0, 1};
  const double dt = 1e-6, spacing = 1e-3;
  const double px = pa.m[0] * pa.v[0].x() + pa.m[1] * pa.v[1].x();
  Model no_image = m;
  no_image.symmetry.clear();
  enforceParticleContact(no_image, dt);
  enforceParticleContact(m, dt);
  // How far A and B (or B's image) still approach beyond what their gap allows, m/s.
  const Reflection image = mirrorImages(m.symmetry)[0];
  const auto overrun = [&](const Particles& p, bool of_image) {
    const Vec3 x_b = of_image ? image.point(p.x[1]) : p.x[1];
    const Vec3 v_b = of_image ? image.vector(p.v[1]) : p.v[1];
    const Vec3 r = p.x[0] - x_b;
    const double vn_min = std::min(-(r.norm() - spacing) / dt, 0.0);
    return vn_min - (p.v[0] - v_b).dot(r.normalized());
  };
  CHECK(overrun(no_image.particles, true) > 10);  // without the image, it would run into A
  CHECK(overrun(pa, false) < 1e-9);
  CHECK(overrun(pa, true) < 1e-9);
  // Momentum along the plane is conserved; across it the plane takes its share.
  CHECK(pa.m[0] * pa.v[0].x() + pa.m[1] * pa.v[1].x() == Approx(px).epsilon(1e-12));
}
