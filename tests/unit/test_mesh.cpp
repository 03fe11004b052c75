// SPDX-License-Identifier: MIT
// Meshing module: Gmsh plates and projectiles (volume, orientation, grading, determinism),
// the .msh reader (valid 2.2 / 4.1 files, located errors) and the quality figures.
#include "core/common/error.hpp"
#include "core/mesh/mesh.hpp"
#include "core/mesh/structured_box.hpp"
#include "core/mesh/untied_parts.hpp"
#include "core/sph/particle_body.hpp"
#include "core/state/model_build.hpp"
#include "tests/support/models.hpp"

#include <catch2/catch.hpp>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

using namespace fesph;

namespace {

bool allPositive(const TetMesh& m) {
  for (const auto& t : m.tets)
    if (!(tetVolume(m.nodes[t[0]], m.nodes[t[1]], m.nodes[t[2]], m.nodes[t[3]]) > 0)) return false;
  return true;
}

/// Every node is used by some tet (compact numbering).
bool compact(const TetMesh& m) {
  std::vector<bool> used(m.nodes.size(), false);
  for (const auto& t : m.tets)
    for (int n : t) used.at(n) = true;
  return std::all_of(used.begin(), used.end(), [](bool u) { return u; });
}

Vec3 boxMin(const TetMesh& m) {
  Vec3 lo = m.nodes.at(0);
  for (const auto& x : m.nodes) lo = lo.cwiseMin(x);
  return lo;
}
Vec3 boxMax(const TetMesh& m) {
  Vec3 hi = m.nodes.at(0);
  for (const auto& x : m.nodes) hi = hi.cwiseMax(x);
  return hi;
}

/// Mean edge length of the tets whose centroid satisfies `select`.
template <class Select>
double meanEdge(const TetMesh& m, Select select) {
  double sum = 0;
  int n = 0;
  for (const auto& t : m.tets) {
    const Vec3 c = 0.25 * (m.nodes[t[0]] + m.nodes[t[1]] + m.nodes[t[2]] + m.nodes[t[3]]);
    if (!select(c)) continue;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) sum += (m.nodes[t[j]] - m.nodes[t[i]]).norm();
    n += 6;
  }
  REQUIRE(n > 0);
  return sum / n;
}

PlateSpec gradedHalfPlate() {  // 40 x 40 x 2 mm, fine 0.5 mm, coarse 2 mm (ratio 4)
  PlateSpec s;
  s.size_x = 0.04; s.size_y = 0.04; s.thickness = 0.002;
  s.refine_radius = 0.003; s.grade_distance = 0.006;
  s.fine_size = 0.0005; s.coarse_size = 0.002;
  s.half = true;
  return s;
}

ProjectileSpec projectile(NoseShape nose, bool half) {  // 10 mm x 20 mm, 1 mm elements
  ProjectileSpec s;
  s.diameter = 0.01; s.length = 0.02; s.nose = nose; s.crh = 2.0;
  s.mesh_size = 0.001; s.half = half;
  return s;
}

/// Tangent-ogive nose + cylinder volume by Simpson's rule on pi r(z)^2, where
/// r(z) = (r - R) + sqrt(R^2 - (z - Ln)^2) on the nose, R = crh d, Ln = sqrt(R^2 - (R - r)^2).
double ogiveVolume(double d, double crh, double length) {
  const double r = 0.5 * d, big_r = crh * d;
  const double nose = std::sqrt(big_r * big_r - (big_r - r) * (big_r - r));
  const auto area = [&](double z) {
    const double rz = (r - big_r) + std::sqrt(big_r * big_r - (z - nose) * (z - nose));
    return M_PI * rz * rz;
  };
  const int n = 2000;  // even; Simpson error ~ 1e-13 relative here
  const double h = nose / n;
  double sum = area(0) + area(nose);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * area(i * h);
  return sum * h / 3.0 + M_PI * r * r * (length - nose);
}

// ---- .msh helpers --------------------------------------------------------------------

std::string dataFile(const std::string& name) {
  return std::string(FESPH_TEST_DATA_DIR) + "/" + name;
}

/// Writes `text` to a per-process temporary file and returns its path.
std::string writeTemp(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("fesph_test_mesh_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(path) << text;
  return path.string();
}

/// A valid 2.2 file: a line element (ignored) and two tets sharing the face 1-2-3, the
/// second given with negative orientation. Total volume 1/6 + 1/6 = 1/3.
const std::vector<std::string> kSmallMsh22 = {
    "$MeshFormat",       // line 1
    "2.2 0 8",           // 2
    "$EndMeshFormat",    // 3
    "$Nodes",            // 4
    "5",                 // 5
    "1 0 0 0",           // 6
    "2 1 0 0",           // 7
    "3 0 1 0",           // 8
    "4 0 0 1",           // 9
    "5 0 0 -1",          // 10
    "$EndNodes",         // 11
    "$Elements",         // 12
    "3",                 // 13
    "1 1 2 0 1 1 2",     // 14
    "2 4 2 0 1 1 2 3 4", // 15
    "3 4 2 0 1 1 2 3 5", // 16
    "$EndElements",      // 17
};

/// kSmallMsh22 with 1-based line `line` replaced by `text`, or cut after line `keep`.
std::string joinLines(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}
std::string smallMshWith(int line, const std::string& text) {
  auto lines = kSmallMsh22;
  lines.at(line - 1) = text;
  return joinLines(lines);
}
std::string smallMshFirst(int keep) {
  return joinLines({kSmallMsh22.begin(), kSmallMsh22.begin() + keep});
}

/// The lines of cube_v41.msh, to be edited into broken 4.1 files.
std::vector<std::string> cubeV41Lines() {
  std::ifstream in(dataFile("cube_v41.msh"));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

/// The InputError readMsh throws for `text`; checks that its message names the file.
InputError readError(const std::string& name, const std::string& text) {
  const std::string path = writeTemp(name, text);
  try {
    readMsh(path);
  } catch (const InputError& e) {
    std::filesystem::remove(path);
    CHECK_THAT(e.what(), Catch::Matchers::Contains(path));
    CHECK(e.file() == path);
    return e;
  }
  std::filesystem::remove(path);
  throw std::runtime_error("readMsh accepted the broken file " + name);
}

}  // namespace

// ---- quality ---------------------------------------------------------------------------

TEST_CASE("meshQuality of a regular tetrahedron", "[unit][mesh]") {
  // Regular tet of edge 2 sqrt(2) inscribed in the cube [-1, 1]^3: q = 1 exactly, dihedral
  // acos(1/3) = 70.528779 deg, V = a^3 / (6 sqrt 2) = 8/3. Tolerance: round-off.
  const TetMesh m{{{1, 1, 1}, {-1, -1, 1}, {-1, 1, -1}, {1, -1, -1}}, {{0, 1, 2, 3}}, {}};
  REQUIRE(allPositive(m));
  const MeshQuality q = meshQuality(m);
  CHECK(q.nodes == 4);
  CHECK(q.elements == 1);
  CHECK(q.min_quality == Approx(1.0).margin(1e-12));
  CHECK(q.mean_quality == Approx(1.0).margin(1e-12));
  CHECK(q.min_dihedral_deg == Approx(std::acos(1.0 / 3.0) * 180.0 / M_PI).epsilon(1e-12));
  CHECK(q.min_dihedral_deg == Approx(70.5288).margin(1e-4));
  CHECK(q.volume == Approx(8.0 / 3.0).epsilon(1e-12));
}

// ---- plates ----------------------------------------------------------------------------

TEST_CASE("meshQuality of a corner tetrahedron, a wedge and an inverted one", "[unit][mesh]") {
  // The unit corner tet (origin and the three unit points): V = 1/6, sum of squared edges
  // 3 + 3 x 2 = 9, so q = 12 (1/2)^(2/3) / 9; dihedral angles 90 deg at the three edges
  // through the origin and acos(1/sqrt 3) = 54.7356 deg at the other three. Turned inside out
  // (two nodes swapped) its shape quality counts as 0 and its volume as -1/6.
  const TetMesh corner{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 1, 2, 3}}, {}};
  const MeshQuality q = meshQuality(corner);
  CHECK(q.min_quality == Approx(12.0 * std::cbrt(0.25) / 9.0).epsilon(1e-12));
  const double shallow = std::acos(1.0 / std::sqrt(3.0)) * 180.0 / M_PI;
  CHECK(q.min_dihedral_deg == Approx(shallow).epsilon(1e-12));
  CHECK(q.volume == Approx(1.0 / 6.0).epsilon(1e-12));
  // A wedge about the z axis (nodes 2, 3 on it, 0 and 1 off it at 0 and atan(0.2) around it):
  // its smallest dihedral angle is at edge 2-3, between the faces opposite nodes 0 and 1.
  const TetMesh wedge{{{1, 0, 0}, {1, 0.2, 0.5}, {0, 0, 0}, {0, 0, 1}}, {{0, 1, 2, 3}}, {}};
  CHECK(meshQuality(wedge).min_dihedral_deg ==
        Approx(std::atan(0.2) * 180.0 / M_PI).epsilon(1e-12));
  const TetMesh inverted{corner.nodes, {{1, 0, 2, 3}}, {}};
  const MeshQuality qi = meshQuality(inverted);
  CHECK(qi.min_quality == 0.0);
  CHECK(qi.volume == Approx(-1.0 / 6.0).epsilon(1e-12));
}

TEST_CASE("meshPlate: graded half plate", "[unit][mesh]") {
  const PlateSpec s = gradedHalfPlate();
  const TetMesh m = meshPlate(s);
  const MeshQuality q = meshQuality(m);
  REQUIRE(q.elements > 0);
  CHECK(allPositive(m));
  CHECK(compact(m));
  // Box volume x*y*t / 2 exactly (planar faces, no facetting): 1e-9 relative.
  CHECK(q.volume == Approx(s.size_x * s.size_y * s.thickness / 2).epsilon(1e-9));
  // Local frame: y in [0, size_y/2], front face z = 0, rear face z = -thickness (round-off).
  CHECK(boxMin(m).isApprox(Vec3(-s.size_x / 2, 0, -s.thickness), 1e-12));
  CHECK(boxMax(m).isApprox(Vec3(s.size_x / 2, s.size_y / 2, 0), 1e-12));
  // Grading, coarse/fine = 4: edges inside the refinement zone are less than half as long as
  // those beyond refine_radius + grade_distance (ideal ratio 1/4).
  const auto dist = [](const Vec3& c) { return std::hypot(c.x(), c.y()); };
  const double fine = meanEdge(m, [&](const Vec3& c) { return dist(c) < s.refine_radius; });
  const double rim = meanEdge(
      m, [&](const Vec3& c) { return dist(c) > s.refine_radius + s.grade_distance; });
  CHECK(fine < 0.5 * rim);
  CHECK(q.min_quality > 0.1);  // usable explicit-dynamics tets
}

TEST_CASE("meshPlate: full plate, offset refinement stretched along x", "[unit][mesh]") {
  PlateSpec s;
  s.size_x = 0.06; s.size_y = 0.03; s.thickness = 0.003;
  s.refine_x = 0.01; s.refine_y = -0.005; s.refine_radius = 0.003; s.refine_stretch_x = 3.0;
  s.fine_size = 0.001; s.coarse_size = 0.004; s.grade_distance = 0.005;
  const TetMesh m = meshPlate(s);
  const MeshQuality q = meshQuality(m);
  CHECK(allPositive(m));
  // Box volume x*y*t: 1e-9 relative.
  CHECK(q.volume == Approx(s.size_x * s.size_y * s.thickness).epsilon(1e-9));
  CHECK(boxMin(m).isApprox(Vec3(-s.size_x / 2, -s.size_y / 2, -s.thickness), 1e-12));
  // With stretch 3, the point 2 radii from the centre along x is inside the fine zone, the one
  // 2 radii along y is 1 radius out (size fine + 3/5 (coarse - fine)): x side must be finer.
  const auto near = [&](double x, double y) {
    return [=](const Vec3& c) { return std::hypot(c.x() - x, c.y() - y) < s.fine_size * 1.5; };
  };
  const double along_x = meanEdge(m, near(s.refine_x + 2 * s.refine_radius, s.refine_y));
  const double along_y = meanEdge(m, near(s.refine_x, s.refine_y + 2 * s.refine_radius));
  CHECK(along_x < along_y);
  CHECK(q.min_quality > 0.1);
}

TEST_CASE("meshPlate rejects an inconsistent spec", "[unit][mesh]") {
  PlateSpec s = gradedHalfPlate();
  s.coarse_size = 0.5 * s.fine_size;
  CHECK_THROWS_AS(meshPlate(s), InputError);
}

// ---- projectiles -----------------------------------------------------------------------

TEST_CASE("meshProjectile: flat cylinder, full and half", "[unit][mesh]") {
  const ProjectileSpec full_spec = projectile(NoseShape::Flat, false);
  const TetMesh full = meshProjectile(full_spec);
  const TetMesh half = meshProjectile(projectile(NoseShape::Flat, true));
  CHECK(allPositive(full));
  CHECK(allPositive(half));
  const double r = 0.005, length = 0.02;
  const double v_full = meshQuality(full).volume, v_half = meshQuality(half).volume;
  // Analytic pi r^2 L; facetting of the 1 mm polygonal rim (r = 5 mm) costs < 1%.
  CHECK(v_full == Approx(M_PI * r * r * length).epsilon(0.01));
  // Half model = full / 2 within 1% (different facetting of the two meshes).
  CHECK(v_half == Approx(v_full / 2).epsilon(0.01));
  // Local frame: tip at z = 0, base at z = length; the half model covers y >= 0 and spans
  // x from -r to r (revolved from +x through +y). Tolerance: round-off.
  CHECK(boxMin(full).z() == Approx(0).margin(1e-12));
  CHECK(boxMax(full).z() == Approx(length).epsilon(1e-12));
  CHECK(boxMin(half).y() == Approx(0).margin(1e-12));
  CHECK(boxMax(half).y() <= r * (1 + 1e-12));
  CHECK(boxMax(half).y() > 0.98 * r);  // a rim node within 11 deg of +y
  CHECK(boxMin(half).x() == Approx(-r).epsilon(1e-12));
  CHECK(boxMax(half).x() == Approx(r).epsilon(1e-12));
  CHECK(meshQuality(full).min_quality > 0.1);
}

TEST_CASE("meshProjectile: hemispherical nose", "[unit][mesh]") {
  const TetMesh m = meshProjectile(projectile(NoseShape::Hemispherical, true));
  CHECK(allPositive(m));
  const double r = 0.005, length = 0.02;
  // Half of (2/3 pi r^3 + pi r^2 (L - r)); facetting < 1.5%.
  const double exact = 0.5 * (2.0 / 3.0 * M_PI * r * r * r + M_PI * r * r * (length - r));
  CHECK(meshQuality(m).volume == Approx(exact).epsilon(0.015));
  CHECK(boxMin(m).z() == Approx(0).margin(1e-12));
}

TEST_CASE("meshProjectile: tangent-ogive nose and cavity", "[unit][mesh]") {
  ProjectileSpec s = projectile(NoseShape::Ogive, true);
  const TetMesh solid = meshProjectile(s);
  CHECK(allPositive(solid));
  const double exact = 0.5 * ogiveVolume(s.diameter, s.crh, s.length);
  // Half of the analytic tangent-ogive body (Simpson); facetting < 1.5%.
  CHECK(meshQuality(solid).volume == Approx(exact).epsilon(0.015));
  CHECK(boxMin(solid).z() == Approx(0).margin(1e-12));

  s.cavity_diameter = 0.004; s.cavity_start = 0.01; s.cavity_end = 0.018;
  const TetMesh hollow = meshProjectile(s);
  CHECK(allPositive(hollow));
  // Cavity pi rc^2 (end - start) / 2 subtracted from the solid body; facetting < 1.5%.
  const double cavity = 0.5 * M_PI * 0.002 * 0.002 * (s.cavity_end - s.cavity_start);
  CHECK(meshQuality(hollow).volume == Approx(exact - cavity).epsilon(0.015));
  // No node inside the cavity (radius 2 mm, 10 to 18 mm), up to round-off.
  const auto inside = [&](const Vec3& x) {
    return std::hypot(x.x(), x.y()) < 0.002 - 1e-9 && x.z() > s.cavity_start + 1e-9 &&
           x.z() < s.cavity_end - 1e-9;
  };
  CHECK(std::none_of(hollow.nodes.begin(), hollow.nodes.end(), inside));
}

TEST_CASE("a plate of bonded layers: each layer a region, tied at the faces between them",
          "[unit][mesh]") {
  // Layers 1, 2 and 1 mm from the front face back, 10 x 8 mm (half: 10 x 4 mm). Reference:
  // each region's volume is its layer's, every tet lies within its layer, and the faces
  // between layers are meshed once (no part untied, no two nodes at one place).
  for (const bool half : {false, true}) {
    PlateSpec p;
    p.size_x = 10e-3;
    p.size_y = 8e-3;
    p.thickness = 4e-3;
    p.layers = {1e-3, 2e-3, 1e-3};
    p.fine_size = p.coarse_size = 1e-3;
    p.grade_distance = 5e-3;
    p.half = half;
    const TetMesh m = meshPlate(p);
    REQUIRE(m.region.size() == m.tets.size());
    const double tops[] = {0, -1e-3, -3e-3, -4e-3};
    double volume[3] = {0, 0, 0};
    for (std::size_t t = 0; t < m.tets.size(); ++t) {
      const auto& c = m.tets[t];
      const int k = m.region[t];
      REQUIRE((k >= 0 && k < 3));
      for (int n : c) {
        CHECK(m.nodes[static_cast<std::size_t>(n)].z() <= tops[k] + 1e-12);
        CHECK(m.nodes[static_cast<std::size_t>(n)].z() >= tops[k + 1] - 1e-12);
      }
      volume[k] += tetVolume(m.nodes[c[0]], m.nodes[c[1]], m.nodes[c[2]], m.nodes[c[3]]);
    }
    const double area = 10e-3 * 8e-3 * (half ? 0.5 : 1.0);
    CHECK(volume[0] == Approx(area * 1e-3).epsilon(1e-9));
    CHECK(volume[1] == Approx(area * 2e-3).epsilon(1e-9));
    CHECK(volume[2] == Approx(area * 1e-3).epsilon(1e-9));
    CHECK(untiedParts(m).faces == 0);
    std::vector<std::array<double, 3>> at;
    for (const Vec3& x : m.nodes) at.push_back({x.x(), x.y(), x.z()});
    std::sort(at.begin(), at.end());
    CHECK(std::adjacent_find(at.begin(), at.end()) == at.end());
  }
  // the layers must make up the thickness
  PlateSpec bad;
  bad.size_x = bad.size_y = 10e-3;
  bad.thickness = 3e-3;
  bad.layers = {1e-3, 1e-3};
  bad.fine_size = bad.coarse_size = 1e-3;
  bad.grade_distance = 5e-3;
  CHECK_THROWS_WITH(meshPlate(bad), Catch::Matchers::Contains("sum to its thickness"));
}

TEST_CASE("Gmsh meshing is deterministic: same spec, same mesh", "[unit][mesh]") {
  ProjectileSpec s = projectile(NoseShape::Ogive, true);
  s.mesh_size = 0.0015;
  const TetMesh a = meshProjectile(s);
  const TetMesh b = meshProjectile(s);
  // Bit-identical: node coordinates compared exactly.
  CHECK(a.nodes == b.nodes);
  CHECK(a.tets == b.tets);
}

TEST_CASE("Gmsh meshing leaves the OpenMP thread count alone", "[unit][mesh]") {
  // gmsh::initialize() sets it to 1 process-wide; the solver must keep its threads.
  const int before = omp_get_max_threads();
  omp_set_num_threads(3);
  PlateSpec s = gradedHalfPlate();
  s.fine_size = s.coarse_size;  // a coarse, quick mesh
  meshPlate(s);
  CHECK(omp_get_max_threads() == 3);
  omp_set_num_threads(before);
}

// ---- .msh reader -----------------------------------------------------------------------

// cube_v41.msh and cube_v22.msh: the same Gmsh 4.8.4 mesh of a 10 mm cube (coordinates in mm,
// Mesh.MeshSizeMax = 6, Delaunay), written as 4.1 and 2.2; 45 nodes, 100 tets, plus points,
// lines and triangles that the reader must skip.
TEST_CASE("readMsh reads Gmsh 4.1 and 2.2 ASCII files", "[unit][mesh]") {
  const TetMesh v41 = readMsh(dataFile("cube_v41.msh"), 1e-3);
  const TetMesh v22 = readMsh(dataFile("cube_v22.msh"));
  CHECK(v41.tets.size() == 100);
  CHECK(v41.nodes.size() == 45);
  CHECK(allPositive(v41));
  CHECK(compact(v41));
  // Cube volume: (10 mm)^3 = 1e-6 m^3 after scaling, 1000 mm^3 unscaled; round-off.
  CHECK(meshQuality(v41).volume == Approx(1e-6).epsilon(1e-12));
  CHECK(meshQuality(v22).volume == Approx(1000).epsilon(1e-12));
  // Same mesh in both formats: same connectivity, coordinates equal up to the scale.
  REQUIRE(v22.nodes.size() == v41.nodes.size());
  CHECK(v22.tets == v41.tets);
  for (std::size_t i = 0; i < v22.nodes.size(); ++i)
    CHECK((1e-3 * v22.nodes[i] - v41.nodes[i]).norm() < 1e-15);
}

TEST_CASE("readMsh reads signed coordinates and any number of element tags", "[unit][mesh]") {
  // Gmsh writes "+1e+00" style numbers in some exports, and 2.2 element lines carry a count
  // of tags (physical, elementary, partitions...) before the nodes.
  auto lines = kSmallMsh22;
  lines.at(9) = "5 +0 -0 -1.0e+0";          // line 10
  lines.at(14) = "2 4 3 0 1 7 1 2 3 4";     // line 15: three tags
  lines.at(15) = "3 4 1 0 1 2 3 5";         // line 16: one tag
  const std::string path = writeTemp("signed.msh", joinLines(lines));
  const TetMesh m = readMsh(path);
  std::filesystem::remove(path);
  REQUIRE(m.tets.size() == 2);
  CHECK(meshQuality(m).volume == Approx(1.0 / 3.0).epsilon(1e-12));
}

TEST_CASE("readMsh orients tets and skips other elements", "[unit][mesh]") {
  const std::string path = writeTemp("small.msh", joinLines(kSmallMsh22));
  const TetMesh m = readMsh(path);
  std::filesystem::remove(path);
  CHECK(m.tets.size() == 2);
  CHECK(m.nodes.size() == 5);
  CHECK(allPositive(m));                                     // the second tet was flipped
  CHECK(meshQuality(m).volume == Approx(1.0 / 3.0).epsilon(1e-14));  // two tets of 1/6
}

TEST_CASE("readMsh takes one physical volume of a mesh with several, by name or tag",
          "[unit][mesh]") {
  // A core and its jacket meshed as one file: each a body of its own material. 2.2: the
  // first element tag is the physical group; 4.1: the element block's volume entity has its
  // physical tags in $Entities. The names come from $PhysicalNames (dimension 3).
  auto lines = kSmallMsh22;
  lines.at(14) = "2 4 2 5 1 1 2 3 4";  // physical 5
  lines.at(15) = "3 4 2 7 1 1 2 3 5";  // physical 7
  lines.insert(lines.begin() + 3,
               {"$PhysicalNames", "3", "3 5 \"core\"", "2 5 \"skin\"", "3 7 \"steel jacket\"",
                "$EndPhysicalNames"});  // tags count per dimension: a surface's 5 is another 5
  const std::string path = writeTemp("groups.msh", joinLines(lines));
  CHECK(readMsh(path).tets.size() == 2);  // every volume
  const TetMesh core = readMsh(path, 1.0, {"core"});
  REQUIRE(core.tets.size() == 1);
  CHECK(core.nodes.size() == 4);  // the nodes of its tet only
  double z_max = 0;
  for (const Vec3& x : core.nodes) z_max = std::max(z_max, x.z());
  CHECK(z_max == 1.0);  // node 4 (0, 0, 1): the first tet's
  const TetMesh jacket = readMsh(path, 1.0, {"steel jacket"});  // a name with a blank
  REQUIRE(jacket.tets.size() == 1);
  for (const Vec3& x : jacket.nodes) CHECK(x.z() <= 0.0);  // node 5 (0, 0, -1), not node 4
  CHECK(readMsh(path, 1.0, {"", 7}).tets.size() == 1);
  // a volume the file lacks (a surface's name is no volume's) names those it has
  for (const MshVolume& missing : {MshVolume{"skin"}, MshVolume{"", 3}}) {
    try {
      readMsh(path, 1.0, missing);
      FAIL("no error");
    } catch (const InputError& e) {
      CHECK_THAT(e.what(), Catch::Matchers::Contains(
                               "the mesh's physical volumes: 5 \"core\", 7 \"steel jacket\""));
    }
  }
  std::filesystem::remove(path);
  // Tets of no physical group (2.2 writes 0 for it) are in no volume a name asks for.
  const std::string untagged = writeTemp("untagged.msh", joinLines(kSmallMsh22));
  CHECK_THROWS_WITH(readMsh(untagged, 1.0, {"core"}),
                    Catch::Matchers::Contains("the mesh's physical volumes: none"));
  std::filesystem::remove(untagged);

  // 4.1: the cube's one volume (entity 1, line 32) given the physical tags 9, named "cube",
  // and 4 (in two groups at once, as Gmsh allows).
  auto v41 = cubeV41Lines();
  REQUIRE(v41.at(31).rfind("1 ", 0) == 0);
  REQUIRE(v41.at(31).find(" 0 6 1 2 3 4 5 6") != std::string::npos);
  v41.at(31).replace(v41.at(31).find(" 0 6 1 2 3 4 5 6"), 16, " 2 9 4 6 1 2 3 4 5 6");
  v41.insert(v41.begin() + 3, {"$PhysicalNames", "1", "3 9 \"cube\"", "$EndPhysicalNames"});
  const std::string p41 = writeTemp("groups41.msh", joinLines(v41));
  CHECK(readMsh(p41, 1e-3, {"cube"}).tets.size() == 100);
  CHECK(readMsh(p41, 1e-3, {"", 9}).tets.size() == 100);
  CHECK(readMsh(p41, 1e-3, {"", 4}).tets.size() == 100);
  CHECK_THROWS_WITH(readMsh(p41, 1e-3, {"core"}),
                    Catch::Matchers::Contains("no tetrahedra in the physical volume \"core\"; "
                                              "the mesh's physical volumes: 4, 9 \"cube\""));
  std::filesystem::remove(p41);
}

TEST_CASE("readMsh takes several physical volumes as one body, tied at their shared nodes",
          "[unit][mesh]") {
  // A core and its jacket meshed conformally: read together, each tet knows its volume (its
  // material) and the two keep the nodes of the face they share, which ties them.
  auto lines = kSmallMsh22;
  lines.at(14) = "2 4 2 5 1 1 2 3 4";  // physical 5, above the face (1 2 3)
  lines.at(15) = "3 4 2 7 1 1 2 3 5";  // physical 7, below it
  auto named = lines;
  named.insert(named.begin() + 3, {"$PhysicalNames", "2", "3 5 \"core\"", "3 7 \"jacket\"",
                                   "$EndPhysicalNames"});
  const std::string path = writeTemp("volumes.msh", joinLines(named));
  const TetMesh both = readMsh(path, 1.0, std::vector<MshVolume>{{"jacket"}, {"", 5}});
  REQUIRE(both.tets.size() == 2);
  CHECK(both.nodes.size() == 5);  // the shared face's three nodes once
  CHECK(both.region == std::vector<int>{1, 0});  // element 2 is the core (5, asked second)
  // every tet must be given a volume: the jacket left out is said, with the first tet's line
  try {
    readMsh(path, 1.0, std::vector<MshVolume>{{"core"}});
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(e.line() == 0);  // the scene's mistake: the scene puts it at the body's line
    CHECK_THAT(e.what(), Catch::Matchers::Contains(
                             "1 of the mesh's 2 tetrahedra are in none of the physical volumes "
                             "given a material (the first: element 3, line 21); the mesh's "
                             "physical volumes: 5 \"core\", 7 \"jacket\""));
  }
  CHECK_THROWS_WITH(readMsh(path, 1.0, std::vector<MshVolume>{{"core"}, {"shell"}}),
                    Catch::Matchers::Contains("no tetrahedra in the physical volume \"shell\""));
  // one volume asked for twice (by name and by tag): its tets would have two materials
  CHECK_THROWS_WITH(readMsh(path, 1.0, std::vector<MshVolume>{{"core"}, {"jacket"}, {"", 5}}),
                    Catch::Matchers::Contains("element 2 (line 20) is in both physical volumes "
                                              "\"core\" and 5: give each tet one material"));
  std::filesystem::remove(path);
}

TEST_CASE("parts of a mesh that touch or overlap without sharing nodes are found",
          "[unit][mesh]") {
  // A body has no contact with itself: its parts are held together only where they share
  // nodes. Reference: a structured bar (conformal: none found), the same bar with its rear
  // half on nodes of its own (the face x = 2 is 2 x 2 squares of two triangles, each a
  // boundary face on both sides: 16 found, on x = 2), the bar and a copy shifted by half a
  // cell (overlap: found), and the bar and a copy 10 % of a cell away (apart: none).
  const TetMesh bar = structuredBox(Vec3::Zero(), Vec3(4, 2, 2), 4, 2, 2);
  CHECK(untiedParts(bar).faces == 0);

  TetMesh split = bar;
  std::vector<int> copy(bar.nodes.size(), -1);
  for (auto& tet : split.tets) {
    double x = 0;
    for (int n : tet) x += 0.25 * bar.nodes[static_cast<std::size_t>(n)].x();
    if (x < 2) continue;
    for (int& n : tet) {
      if (copy[static_cast<std::size_t>(n)] < 0) {
        copy[static_cast<std::size_t>(n)] = static_cast<int>(split.nodes.size());
        split.nodes.push_back(bar.nodes[static_cast<std::size_t>(n)]);
      }
      n = copy[static_cast<std::size_t>(n)];
    }
  }
  const UntiedContact found = untiedParts(split);
  CHECK(found.faces == 16);
  CHECK(found.centre.x() == Approx(2.0).margin(1e-12));
  CHECK(found.tet != found.other);

  const auto twoBars = [&](const Vec3& shift) {
    TetMesh two = bar;
    const int offset = static_cast<int>(bar.nodes.size());
    for (const Vec3& x : bar.nodes) two.nodes.push_back(x + shift);
    for (auto tet : bar.tets) {
      for (int& n : tet) n += offset;
      two.tets.push_back(tet);
    }
    return two;
  };
  CHECK(untiedParts(twoBars(Vec3(0.5, 0.5, 0))).faces > 0);
  CHECK(untiedParts(twoBars(Vec3(4.1, 0, 0))).faces == 0);
}

TEST_CASE("readMsh reports bad files at their line", "[unit][mesh]") {
  SECTION("missing file") {
    const std::string path = dataFile("no_such_file.msh");
    try {
      readMsh(path);
      FAIL("no error");
    } catch (const InputError& e) {
      CHECK(e.line() == 0);
      CHECK_THAT(e.what(), Catch::Matchers::Contains("cannot open"));
    }
  }
  SECTION("binary header") {
    const InputError e = readError("binary.msh", smallMshWith(2, "2.2 1 8"));
    CHECK(e.line() == 2);
    CHECK_THAT(e.what(), Catch::Matchers::Contains("binary .msh not supported: save as ASCII"));
  }
  SECTION("unknown version") {  // 2.x and 4.1 only: 4.0 laid its sections out otherwise
    for (const char* header : {"3.0 0 8", "4.0 0 8", "4.2 0 8", "1.0 0 8"}) {
      const InputError e = readError("version.msh", smallMshWith(2, header));
      INFO(header);
      CHECK(e.line() == 2);
      CHECK_THAT(e.what(), Catch::Matchers::Contains("expected 2.2 or 4.1"));
    }
  }
  SECTION("truncated file") {
    const InputError e = readError("truncated.msh", smallMshFirst(15));
    CHECK(e.line() == 15);
    CHECK_THAT(e.what(), Catch::Matchers::Contains("premature end of file"));
  }
  SECTION("non-numeric token") {
    const InputError e = readError("token.msh", smallMshWith(8, "3 0 abc 0"));
    CHECK(e.line() == 8);
    CHECK_THAT(e.what(), Catch::Matchers::Contains("'abc'"));
  }
  SECTION("element referencing an undefined node") {
    const InputError e = readError("undefined.msh", smallMshWith(16, "3 4 2 0 1 1 2 3 9"));
    CHECK(e.line() == 16);
    CHECK_THAT(e.what(), Catch::Matchers::Contains("undefined node 9"));
  }
  SECTION("a node defined twice") {  // which of the two would the tets mean?
    const InputError e = readError("twice.msh", smallMshWith(10, "4 0 0 -1"));
    CHECK(e.line() == 10);
    CHECK_THAT(e.what(), Catch::Matchers::Contains("node 4 defined twice"));
  }
  SECTION("zero-volume tet") {  // node 5 moved into the plane of nodes 1, 2, 3
    CHECK(readError("flat.msh", smallMshWith(10, "5 1 1 0")).line() == 16);
  }
  SECTION("no tetrahedra") {
    auto lines = kSmallMsh22;
    lines.erase(lines.begin() + 14, lines.begin() + 16);  // drop both tets
    lines.at(12) = "1";
    CHECK(readError("notets.msh", joinLines(lines)).line() == 12);
  }
  SECTION("a coordinate that is not a finite number") {
    for (const char* node : {"5 nan 0 -1", "5 0 inf -1"}) {
      const InputError e = readError("nan.msh", smallMshWith(10, node));
      CHECK(e.line() == 10);
      CHECK_THAT(e.what(), Catch::Matchers::Contains("(a finite number)"));
    }
  }
  SECTION("a negative count") {
    const InputError e = readError("count.msh", smallMshWith(13, "-1"));
    CHECK(e.line() == 13);
    CHECK_THAT(e.what(), Catch::Matchers::Contains("the number of elements >= 0"));
  }
  SECTION("a tetrahedron with five node tags") {
    const InputError e = readError("five.msh", smallMshWith(16, "3 4 2 0 1 1 2 3 5 4"));
    CHECK(e.line() == 16);
    CHECK_THAT(e.what(), Catch::Matchers::Contains("expected 4 node tags for tetrahedron 3"));
  }
  SECTION("a volume element that is no 4-node tetrahedron") {
    // Skipped, a hexahedron or a 10-node tet would leave a hole in the body, or a body of
    // the wrong volume: refused at its line, naming what it is (GmshDefines.h types).
    const InputError hex = readError("hex.msh", smallMshWith(16, "3 5 2 0 1 1 2 3 5 1 2 3 4"));
    CHECK(hex.line() == 16);
    CHECK_THAT(hex.what(), Catch::Matchers::Contains(
                               "element 3 is a 8-node hexahedron (Gmsh type 5): fesph reads "
                               "4-node tetrahedra only"));
    const InputError tet10 =
        readError("tet10.msh", smallMshWith(15, "2 11 2 0 1 1 2 3 4 1 2 3 4 5 1"));
    CHECK(tet10.line() == 15);
    CHECK_THAT(tet10.what(),
               Catch::Matchers::Contains("element 2 is a 10-node tetrahedron (Gmsh type 11)"));
    // 4.1: the cube's volume block (line 298, 100 tets from line 299) given as prisms, and as
    // a type this reader has no name for; any type in a volume entity is a volume element.
    auto lines = cubeV41Lines();
    REQUIRE(lines.at(297) == "3 1 4 100");
    lines.at(297) = "3 1 6 100";
    const InputError prism = readError("prism41.msh", joinLines(lines));
    CHECK(prism.line() == 299);
    CHECK_THAT(prism.what(), Catch::Matchers::Contains("is a 6-node prism (Gmsh type 6)"));
    lines.at(297) = "3 1 99 100";
    CHECK_THAT(readError("other41.msh", joinLines(lines)).what(),
               Catch::Matchers::Contains("is a volume element (Gmsh type 99)"));
  }
  SECTION("a line outside any section") {
    auto lines = kSmallMsh22;
    lines.insert(lines.begin() + 11, "stray text");  // after $EndNodes: line 12
    const InputError e = readError("stray.msh", joinLines(lines));
    CHECK(e.line() == 12);
    CHECK_THAT(e.what(), Catch::Matchers::Contains("expected a section header"));
  }
  SECTION("a scale that is not a positive finite number") {
    const std::string path = writeTemp("scale.msh", joinLines(kSmallMsh22));
    for (double scale : {0.0, -1.0, std::numeric_limits<double>::infinity()})
      CHECK_THROWS_WITH(readMsh(path, scale),
                        Catch::Matchers::Contains("mesh scale must be a positive number"));
    std::filesystem::remove(path);
  }
  SECTION("4.1 node blocks: parametric coordinates promised and missing, a dimension of 4") {
    // Line 60 of cube_v41.msh opens a block of one node on a curve (dimension 1); with the
    // parametric flag set, its coordinate line (62) must hold x y z and u.
    auto lines = cubeV41Lines();
    REQUIRE(lines.at(59) == "1 1 0 1");
    lines.at(59) = "1 1 1 1";
    const InputError e = readError("parametric.msh", joinLines(lines));
    CHECK(e.line() == 62);
    CHECK_THAT(e.what(), Catch::Matchers::Contains("expected node coordinates"));
    // and a block of an entity of dimension 4 (line 36 opens the first block, on a point)
    lines = cubeV41Lines();
    REQUIRE(lines.at(35) == "0 1 0 1");
    lines.at(35) = "4 1 0 1";
    const InputError d = readError("dimension.msh", joinLines(lines));
    CHECK(d.line() == 36);
    CHECK_THAT(d.what(), Catch::Matchers::Contains("expected an entity dimension 0 to 3"));
  }
  SECTION("truncated 4.1 file") {
    const auto lines = cubeV41Lines();
    REQUIRE(lines.size() > 300);
    CHECK(readError("truncated41.msh", joinLines({lines.begin(), lines.begin() + 300})).line() ==
          300);  // inside $Elements
  }
}

TEST_CASE("a flat or inverted tetrahedron, a loose node or an empty particle is refused",
          "[unit][mesh]") {
  // What a hand-made or converted mesh can hold and a run cannot: a tetrahedron of no or
  // negative volume (its stiffness and step are undefined), a node in no tetrahedron (no
  // mass), a particle of no volume. Each is refused by name before any step.
  const auto error = [](const std::vector<Vec3>& nodes, const std::array<int, 4>& tet) {
    Model model;
    model.materials.push_back(testing::elasticMaterial());
    try {
      addBody(model, "b", TetMesh{nodes, {tet}, {}}, 0, Placement{}, Vec3::Zero(), false);
      finaliseModel(model);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const double s = 1e-3;
  const std::vector<Vec3> corners = {Vec3(0, 0, 0), Vec3(s, 0, 0), Vec3(0, s, 0), Vec3(0, 0, s)};
  CHECK(error(corners, {0, 1, 2, 3}).empty());
  CHECK(error({corners[0], corners[1], corners[2], Vec3(s, s, 0)}, {0, 1, 2, 3})
            .find("body 'b': tetrahedron 0 has non-positive volume") != std::string::npos);
  CHECK(error(corners, {1, 0, 2, 3}).find("tetrahedron 0 has non-positive volume") !=
        std::string::npos);
  std::vector<Vec3> loose = corners;
  loose.push_back(Vec3(s, s, s));
  CHECK(error(loose, {0, 1, 2, 3}).find("node 4 of body 'b' belongs to no tetrahedron") !=
        std::string::npos);

  Model model;
  model.materials.push_back(testing::elasticMaterial());
  CHECK_NOTHROW(addParticleBody(model, "p", {Vec3::Zero()}, {1e-9}, 0, Vec3::Zero(), false, 1.3));
  try {
    addParticleBody(model, "q", {Vec3::Zero(), Vec3::UnitX()}, {1e-9, 0.0}, 0, Vec3::Zero(),
                    false, 1.3);
    FAIL("a particle of no volume accepted");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("body 'q': particle 1 has non-positive volume") !=
          std::string::npos);
  }
}

TEST_CASE("a body's mass and velocity count its own points, which start in the rest state",
          "[unit][mesh]") {
  // bodyMass and bodyMeanVelocity (the history's body velocities, the residual velocity's
  // mass fractions): a tetrahedron of elements and two particle bodies, each its own.
  Model model;
  model.materials.push_back(testing::elasticMaterial(8000));
  model.materials[0].T_room = 250.0;  // not PointState's default
  const double s = 1e-3;
  addBody(model, "tet", TetMesh{{Vec3(0, 0, 0), Vec3(s, 0, 0), Vec3(0, s, 0), Vec3(0, 0, s)},
                                {{0, 1, 2, 3}}, {}},
          0, Placement{}, Vec3(1, 0, 0), false);
  addParticleBody(model, "p", {Vec3(0, 0, 1), Vec3(0, 0, 2)}, {1e-9, 3e-9}, 0, Vec3(0, 2, 0),
                  false, 1.3);
  addParticleBody(model, "q", {Vec3(0, 0, 3)}, {5e-9}, 0, Vec3(0, 0, 4), true, 1.5);
  finaliseModel(model);
  model.particles.v[1] = Vec3(0, 6, 0);  // p: 1e-9 at 2 m/s, 3e-9 at 6 m/s
  const double rho = 8000, tet = s * s * s / 6;
  CHECK(bodyMass(model, 0) == Approx(rho * tet).epsilon(1e-14));
  CHECK(bodyMass(model, 1) == Approx(rho * 4e-9).epsilon(1e-14));
  CHECK(bodyMass(model, 2) == Approx(rho * 5e-9).epsilon(1e-14));
  CHECK((bodyMeanVelocity(model, 0) - Vec3(1, 0, 0)).norm() < 1e-14);
  CHECK((bodyMeanVelocity(model, 1) - Vec3(0, 5, 0)).norm() < 1e-14);  // (2 + 3 x 6) / 4
  CHECK((bodyMeanVelocity(model, 2) - Vec3(0, 0, 4)).norm() < 1e-14);
  // every point starts at its material's room temperature
  CHECK(model.elems.state[0].T == 250.0);
  for (const PointState& st : model.particles.state) CHECK(st.T == 250.0);
  // particles at their material's density exactly (8000 x 1e-9 / 1e-9 is not 8000 in
  // doubles: no pressure at rest), h = kappa cbrt(V) with the body's kappa
  for (double rho : model.particles.rho) CHECK(rho == 8000.0);
  CHECK(model.particles.h[0] == Approx(1.3 * std::cbrt(1e-9)).epsilon(1e-15));
  CHECK(model.particles.h[2] == Approx(1.5 * std::cbrt(5e-9)).epsilon(1e-15));
}
