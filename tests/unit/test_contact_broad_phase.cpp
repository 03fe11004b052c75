// SPDX-License-Identifier: MIT
// Contact broad phase against the brute force over all (slave node, face) pairs on random
// configurations: the same candidate lists, in the same order, for any thread count.
#include "core/contact/broad_phase.hpp"
#include "core/contact/surfaces.hpp"
#include "tests/support/models.hpp"

#include <catch2/catch.hpp>

#include <random>

#ifdef _OPENMP
#include <omp.h>
#endif

using namespace fesph;

namespace {

// Three boxes at random places and sizes, nodes jiggled, random velocities, some elements
// deleted, some nodes inactive.
Model randomModel(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Model m;
  m.materials.push_back(fesph::testing::elasticMaterial());
  for (int b = 0; b < 3; ++b) {
    const Vec3 size(2e-3 + 3e-3 * u(rng), 2e-3 + 3e-3 * u(rng), 1e-3 + 3e-3 * u(rng));
    TetMesh mesh = structuredBox(Vec3::Zero(), size, 4 + b, 5, 3 + (b + 1) % 3);
    for (Vec3& x : mesh.nodes) x += 0.05e-3 * Vec3(u(rng), u(rng), u(rng));
    Placement p;
    p.rotation = Eigen::AngleAxisd(u(rng), Vec3(u(rng), u(rng), 1.0).normalized()).matrix();
    p.translation = 3e-3 * Vec3(u(rng), u(rng), u(rng));
    addBody(m, "box" + std::to_string(b), mesh, 0, p, Vec3::Zero(), false);
  }
  finaliseModel(m);
  for (Vec3& v : m.nodes.v) v = 200.0 * Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
  buildSurfaces(m);
  for (std::size_t e = 0; e < m.elems.size(); ++e)
    if (u(rng) < 0.15) {
      m.elems.status[e] = ElemStatus::Eroded;
      removeElementFromSurfaces(m, e);
    }
  for (double& mass : m.nodes.m)
    if (u(rng) < 0.05) mass = 0;
  return m;
}

// Reference: every pair tested, with the criterion of findContactCandidates' contract.
ContactCandidates bruteForce(const Model& m, double dt, double tol_fraction) {
  const Nodes& nd = m.nodes;
  const Surfaces& s = m.surfaces;
  std::vector<Vec3> flo, fhi;
  for (const ExteriorFace& f : s.exterior) {
    Vec3 lo = nd.x[f.node[0]], hi = lo;
    double longest = 0;
    for (int i = 0; i < 3; ++i) {
      const Vec3& x = nd.x[f.node[i]];
      const Vec3 y = x + dt * nd.v[f.node[i]];
      lo = lo.cwiseMin(x).cwiseMin(y);
      hi = hi.cwiseMax(x).cwiseMax(y);
      longest = std::max(longest, (nd.x[f.node[(i + 1) % 3]] - x).norm());
    }
    flo.push_back(lo.array() - tol_fraction * longest);
    fhi.push_back(hi.array() + tol_fraction * longest);
  }
  ContactCandidates c;
  c.body_begin.push_back(0);
  c.offset.push_back(0);
  for (const std::vector<int>& list : s.slave_nodes) {
    for (int a : list) {
      if (!(nd.m[a] > 0)) continue;
      c.slaves.push_back(a);
      const Vec3 y = nd.x[a] + dt * nd.v[a];
      const Vec3 lo = nd.x[a].cwiseMin(y), hi = nd.x[a].cwiseMax(y);
      for (std::size_t f = 0; f < s.exterior.size(); ++f)
        if (s.exterior[f].body != nd.body[a] && (lo.array() <= fhi[f].array()).all() &&
            (flo[f].array() <= hi.array()).all())
          c.faces.push_back(static_cast<int>(f));
      if (c.faces.size() > c.offset.back())
        c.active.push_back(static_cast<int>(c.slaves.size()) - 1);
      c.offset.push_back(c.faces.size());
    }
    c.body_begin.push_back(c.slaves.size());
  }
  return c;
}

/// The broad phase's lists equal the reference's, all of them.
void requireSameCandidates(const ContactCandidates& got, const ContactCandidates& ref) {
  REQUIRE(got.slaves == ref.slaves);
  REQUIRE(got.body_begin == ref.body_begin);
  REQUIRE(got.offset == ref.offset);
  REQUIRE(got.faces == ref.faces);
  REQUIRE(got.active == ref.active);
}

int threads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

void setThreads(int n) {
#ifdef _OPENMP
  omp_set_num_threads(n);
#else
  (void)n;
#endif
}

}  // namespace

TEST_CASE("broad phase = brute force on random configurations", "[unit][contact]") {
  // Reference: exhaustive pair test; exact equality of the candidate lists.
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::size_t total_pairs = 0;
  const int default_threads = threads();
  for (int trial = 0; trial < 20; ++trial) {
    Model m = randomModel(rng);
    const double dt = 1e-6 * u(rng), tol = 0.3 * u(rng);
    const ContactCandidates ref = bruteForce(m, dt, tol);
    for (int threads : {1, 2, 3}) {
      setThreads(threads);
      findContactCandidates(m, dt, tol);
      requireSameCandidates(m.surfaces.candidates, ref);
    }
    total_pairs += ref.faces.size();
  }
  setThreads(default_threads);
  INFO("candidate pairs over all trials: " << total_pairs);
  REQUIRE(total_pairs > 1000);  // the configurations do bring bodies near each other
}

TEST_CASE("broad phase after the face count drops below its parallel threshold",
          "[unit][contact]") {
  // The scratch is kept between steps. With few faces the face pass runs on one thread; the
  // lists of the other threads from an earlier, larger call must not come back (they held
  // faces of that call: stale candidates, indices past the face count). Reference: brute force.
  std::mt19937 rng(7);
  Model big = randomModel(rng);
  REQUIRE(big.surfaces.exterior.size() > 256);
  const int default_threads = threads();
  setThreads(2);
  findContactCandidates(big, 1e-6, 0.2);

  Model small;
  small.materials.push_back(fesph::testing::elasticMaterial());
  for (int b = 0; b < 2; ++b) {
    Placement p;
    p.translation = Vec3(1.5e-3 * b, 0.2e-3 * b, 0.1e-3 * b);
    const TetMesh cube = structuredBox(Vec3::Zero(), Vec3::Constant(2e-3), 2, 2, 2);
    addBody(small, "cube" + std::to_string(b), cube, 0, p, Vec3::Zero(), false);
  }
  finaliseModel(small);
  buildSurfaces(small);
  REQUIRE(small.surfaces.exterior.size() <= 256);
  small.surfaces.scratch = big.surfaces.scratch;
  findContactCandidates(small, 1e-6, 0.2);
  setThreads(default_threads);
  const ContactCandidates ref = bruteForce(small, 1e-6, 0.2);
  REQUIRE(ref.faces.size() > 0);
  requireSameCandidates(small.surfaces.candidates, ref);
}

TEST_CASE("broad phase hashes only the faces near another body's slaves", "[unit][contact]") {
  // Three 4 mm plates side by side along x, 0.5 mm apart; the middle one moves towards the
  // first at 400 m/s. Over a 1 us step only the facing sides of the first two come within
  // reach of each other: the third plate's faces and slaves stay out of the hash. The
  // candidates still equal the brute force (reference) for 1 and 2 threads.
  Model m;
  m.materials.push_back(fesph::testing::elasticMaterial());
  for (int b = 0; b < 3; ++b) {
    Placement p;
    p.translation = Vec3(4.5e-3 * b, 0, 0);
    const TetMesh plate = structuredBox(Vec3::Zero(), Vec3(4e-3, 4e-3, 1e-3), 8, 8, 2);
    addBody(m, "plate" + std::to_string(b), plate, 0, p, Vec3::Zero(), false);
  }
  finaliseModel(m);
  for (std::size_t a = 0; a < m.nodes.size(); ++a)
    if (m.nodes.body[a] == 1) m.nodes.v[a] = Vec3(-400.0, 0, 0);
  buildSurfaces(m);
  const double dt = 1e-6, tol = 0.2;
  const ContactCandidates ref = bruteForce(m, dt, tol);
  REQUIRE(ref.faces.size() > 0);
  const int default_threads = threads();
  for (int threads : {1, 2}) {
    setThreads(threads);
    findContactCandidates(m, dt, tol);
    requireSameCandidates(m.surfaces.candidates, ref);
    // Every hashed face lies on the facing sides (x within 1 mm of the gap at 4 - 4.5 mm).
    const std::vector<int>& hashed = m.surfaces.scratch.bucket_faces;
    REQUIRE(!hashed.empty());
    for (int f : hashed) {
      CAPTURE(f);
      REQUIRE(m.surfaces.exterior[static_cast<std::size_t>(f)].body <= 1);
      for (int a : m.surfaces.exterior[static_cast<std::size_t>(f)].node)
        REQUIRE(std::abs(m.nodes.x[a].x() - 4.25e-3) < 1e-3);
    }
  }
  setThreads(default_threads);
}
