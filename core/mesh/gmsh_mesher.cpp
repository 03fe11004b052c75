// SPDX-License-Identifier: MIT
// Plates and revolved projectiles meshed with the Gmsh C++ API (OpenCASCADE geometry, Delaunay
// tets). One Gmsh session per call with fixed options, so the same spec gives the same mesh.
#include "core/common/error.hpp"
#include "core/mesh/mesh.hpp"
#include "core/mesh/tet_assembly.hpp"

#include <gmsh.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <sstream>
#include <utility>

namespace fesph {
namespace {

constexpr int kLinearTet = 4;  // Gmsh element type

[[noreturn]] void badSpec(const std::string& what) { throw InputError("", 0, 0, what); }

/// Owns Gmsh's global state for one meshing call. Gmsh is not re-entrant, hence the lock;
/// gmsh::initialize() sets the process-wide OpenMP thread count to 1, hence the restore.
class GmshSession {
 public:
  GmshSession() : lock_(mutex()), omp_threads_(omp_get_max_threads()) {
    gmsh::initialize(0, nullptr, false);  // no gmshrc: a user's config must not change meshes
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.NumThreads", 1);  // one thread: reproducible Delaunay
    gmsh::option::setNumber("Mesh.Algorithm3D", 1);
    gmsh::option::setNumber("Mesh.Optimize", 1);
    // Sizes come only from the options and fields set by the caller.
    gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
    gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
    gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
    gmsh::model::add("fesph");
  }
  ~GmshSession() {
    gmsh::finalize();
    omp_set_num_threads(omp_threads_);
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  std::lock_guard<std::mutex> lock_;
  int omp_threads_;
};

/// The linear tets of the current Gmsh model, oriented and compactly numbered.
TetMesh extractTets(const std::string& body) {
  std::vector<std::size_t> node_tags, elem_tags, elem_nodes;
  std::vector<double> coord, param;
  gmsh::model::mesh::getNodes(node_tags, coord, param, -1, -1, false, false);
  gmsh::model::mesh::getElementsByType(kLinearTet, elem_tags, elem_nodes);
  if (elem_tags.empty()) badSpec(body + ": Gmsh produced no tetrahedra");

  // Gmsh node tags are dense (1..n), so a plain vector maps them to positions.
  const std::size_t max_tag = *std::max_element(node_tags.begin(), node_tags.end());
  std::vector<int> index(max_tag + 1, -1);
  std::vector<Vec3> nodes(node_tags.size());
  for (std::size_t i = 0; i < node_tags.size(); ++i) {
    nodes[i] = Vec3(coord[3 * i], coord[3 * i + 1], coord[3 * i + 2]);
    index[node_tags[i]] = static_cast<int>(i);
  }
  std::vector<std::array<int, 4>> tets(elem_tags.size());
  for (std::size_t e = 0; e < tets.size(); ++e) {
    for (int k = 0; k < 4; ++k) tets[e][k] = index[elem_nodes[4 * e + k]];
    const auto& t = tets[e];
    if (mesh_detail::isFlatTet(nodes[t[0]], nodes[t[1]], nodes[t[2]], nodes[t[3]]))
      badSpec(body + ": Gmsh produced a flat tetrahedron; change the mesh sizes");
  }
  return mesh_detail::assembleTetMesh(nodes, std::move(tets));
}

/// Runs `build` (geometry and size settings) in a fresh session, meshes in 3-D and returns
/// the tets. Gmsh reports errors by throwing std::string.
template <class Build>
TetMesh meshWithGmsh(const std::string& body, Build build) {
  GmshSession session;
  try {
    build();
    gmsh::model::occ::synchronize();
    gmsh::model::mesh::generate(3);
    return extractTets(body);
  } catch (const std::string& gmsh_error) {
    badSpec(body + ": Gmsh failed: " + gmsh_error);
  }
}

/// A number for a MathEval expression, in parentheses: Gmsh's parser rejects "x - -1", and a
/// parse error there aborts the process instead of throwing.
std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << '(' << v << ')';
  return s.str();
}

void checkPlate(const PlateSpec& s) {
  if (!(s.size_x > 0 && s.size_y > 0 && s.thickness > 0))
    badSpec("plate: size_x, size_y and thickness must be > 0");
  double sum = 0;
  for (double t : s.layers) {
    if (!(t > 0)) badSpec("plate: every layer's thickness must be > 0");
    sum += t;
  }
  if (!s.layers.empty() && std::abs(sum - s.thickness) > 1e-9 * s.thickness)
    badSpec("plate: the layers' thicknesses must sum to its thickness");
  if (!(s.fine_size > 0 && s.coarse_size >= s.fine_size))
    badSpec("plate: need 0 < fine_size <= coarse_size");
  if (!(s.grade_distance > 0 && s.refine_radius >= 0 && s.refine_stretch_x > 0))
    badSpec("plate: need grade_distance > 0, refine_radius >= 0, refine_stretch_x > 0");
}

/// Background size: fine within the (x-stretched) refinement ellipse, then linear to coarse
/// over grade_distance. Constant through the thickness.
void setPlateSizeField(const PlateSpec& s) {
  const std::string dist = "Sqrt(((x - " + num(s.refine_x) + ") / " + num(s.refine_stretch_x) +
                           ")^2 + (y - " + num(s.refine_y) + ")^2)";
  const std::string ramp = num(s.fine_size) + " + " + num(s.coarse_size - s.fine_size) +
                           " * (" + dist + " - " + num(s.refine_radius) + ") / " +
                           num(s.grade_distance);
  const int field = gmsh::model::mesh::field::add("MathEval");
  gmsh::model::mesh::field::setString(
      field, "F", "Min(" + num(s.coarse_size) + ", Max(" + num(s.fine_size) + ", " + ramp + "))");
  gmsh::model::mesh::field::setAsBackgroundMesh(field);
}

/// A closed polygonal face in the x-z plane (y = 0) through the (x, z) points.
int addProfileFace(const std::vector<std::pair<double, double>>& xz) {
  std::vector<int> pts, lines;
  for (const auto& p : xz) pts.push_back(gmsh::model::occ::addPoint(p.first, 0, p.second));
  for (std::size_t i = 0; i < pts.size(); ++i)
    lines.push_back(gmsh::model::occ::addLine(pts[i], pts[(i + 1) % pts.size()]));
  return gmsh::model::occ::addPlaneSurface({gmsh::model::occ::addCurveLoop(lines)});
}

/// Profile of the solid body (without cavity) in the x-z half plane: x = radius, z = axis.
int addOuterProfile(const ProjectileSpec& s) {
  namespace occ = gmsh::model::occ;
  const double r = 0.5 * s.diameter, nose = noseLength(s);
  if (s.nose == NoseShape::Flat)
    return addProfileFace({{0, 0}, {r, 0}, {r, s.length}, {0, s.length}});
  // Arc centre: on the axis for a hemisphere, at x = r - R (across the axis) for an ogive;
  // either way on the plane z = nose, so the arc meets the shank tangentially.
  const double cx = s.nose == NoseShape::Hemispherical ? 0.0 : r - s.crh * s.diameter;
  const int tip = occ::addPoint(0, 0, 0), centre = occ::addPoint(cx, 0, nose);
  const int shoulder = occ::addPoint(r, 0, nose), base = occ::addPoint(r, 0, s.length);
  const int axis_base = occ::addPoint(0, 0, s.length);
  const int arc = occ::addCircleArc(tip, centre, shoulder);
  occ::remove({{0, centre}});  // a construction point, not part of the body
  const int loop = occ::addCurveLoop({arc, occ::addLine(shoulder, base),
                                      occ::addLine(base, axis_base), occ::addLine(axis_base, tip)});
  return occ::addPlaneSurface({loop});
}

void checkProjectile(const ProjectileSpec& s) {
  if (!(s.diameter > 0 && s.mesh_size > 0)) badSpec("projectile: need diameter, mesh_size > 0");
  if (s.nose == NoseShape::Ogive && !(s.crh >= 0.5)) badSpec("projectile: ogive needs crh >= 0.5");
  if (!(s.length > noseLength(s))) badSpec("projectile: length must exceed the nose length");
  if (s.cavity_diameter == 0) return;
  if (!(s.cavity_diameter > 0 && s.cavity_diameter < s.diameter))
    badSpec("projectile: need 0 < cavity_diameter < diameter");
  if (!(0 <= s.cavity_start && s.cavity_start < s.cavity_end && s.cavity_end <= s.length))
    badSpec("projectile: need 0 <= cavity_start < cavity_end <= length");
}

/// Builds the profile (minus the cavity) and revolves it about z: pi from +x through +y to
/// -x for a half model, 2 pi for a full one.
void buildProjectile(const ProjectileSpec& s) {
  namespace occ = gmsh::model::occ;
  gmsh::vectorpair profile{{2, addOuterProfile(s)}};
  if (s.cavity_diameter > 0) {
    const double rc = 0.5 * s.cavity_diameter;
    const int cavity = addProfileFace(
        {{0, s.cavity_start}, {rc, s.cavity_start}, {rc, s.cavity_end}, {0, s.cavity_end}});
    gmsh::vectorpair cut;
    std::vector<gmsh::vectorpair> cut_map;
    occ::cut(profile, {{2, cavity}}, cut, cut_map);
    profile = cut;
  }
  gmsh::vectorpair revolved;
  occ::revolve(profile, 0, 0, 0, 0, 0, 1, s.half ? M_PI : 2.0 * M_PI, revolved);
  gmsh::option::setNumber("Mesh.MeshSizeMax", s.mesh_size);
}

}  // namespace

TetMesh meshPlate(const PlateSpec& spec) {
  checkPlate(spec);
  // One box per layer, fragmented so that the faces between them are meshed once (shared).
  std::vector<double> fronts = {0.0};  // the layers' front faces, then the rear face
  for (double t : spec.layers) fronts.push_back(fronts.back() - t);
  if (spec.layers.empty()) fronts.push_back(-spec.thickness);
  TetMesh mesh = meshWithGmsh("plate", [&] {
    namespace occ = gmsh::model::occ;
    const double y0 = spec.half ? 0.0 : -0.5 * spec.size_y;
    gmsh::vectorpair boxes;
    for (std::size_t k = 0; k + 1 < fronts.size(); ++k)
      boxes.emplace_back(3, occ::addBox(-0.5 * spec.size_x, y0, fronts[k + 1], spec.size_x,
                                        spec.size_y * (spec.half ? 0.5 : 1.0),
                                        fronts[k] - fronts[k + 1]));
    if (boxes.size() > 1) {
      gmsh::vectorpair fragments;
      std::vector<gmsh::vectorpair> map;
      occ::fragment({boxes.front()}, {boxes.begin() + 1, boxes.end()}, fragments, map);
    }
    setPlateSizeField(spec);
  });
  if (spec.layers.empty()) return mesh;
  mesh.region.resize(mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    double z = 0;
    for (int n : mesh.tets[t]) z += 0.25 * mesh.nodes[static_cast<std::size_t>(n)].z();
    int layer = 0;
    while (layer + 2 < static_cast<int>(fronts.size()) && z < fronts[layer + 1]) ++layer;
    mesh.region[t] = layer;
  }
  return mesh;
}

TetMesh meshProjectile(const ProjectileSpec& spec) {
  checkProjectile(spec);
  return meshWithGmsh("projectile", [&spec] { buildProjectile(spec); });
}

}  // namespace fesph
