// SPDX-License-Identifier: MIT
// Tetrahedral meshes of the bodies: plates and revolved projectiles built with the Gmsh C++ API,
// Gmsh .msh import, and mesh quality figures. Meshes come in the body's local frame (see specs).
#pragma once

#include "core/common/types.hpp"

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace fesph {

/// A tetrahedral mesh. Every tet is positively oriented (det[x1-x0, x2-x0, x3-x0] > 0).
struct TetMesh {
  std::vector<Vec3> nodes;                ///< m
  std::vector<std::array<int, 4>> tets;   ///< node ids
  /// Per tet, which of the mesh's volumes it is in (a physical volume of readMsh's several,
  /// a plate's layer: each of its own material); empty: one volume.
  std::vector<int> region;
};

/// Flat rectangular plate in its local frame: x in [-size_x/2, size_x/2], y in
/// [-size_y/2, size_y/2], front face at z = 0, rear face at z = -thickness (normal +z faces
/// the incoming projectile). Graded: `fine_size` within `refine_radius` of (refine_x,
/// refine_y) (stretched along x by `refine_stretch_x`), growing to `coarse_size` at
/// `refine_radius + grade_distance`. `half` keeps only y >= 0 (cut on the plane y = 0).
struct PlateSpec {
  double size_x = 0, size_y = 0, thickness = 0;
  /// Bonded layers, their thicknesses from the front face back (summing to `thickness`):
  /// each a volume of its own sharing the nodes of the faces between them (tied), its index
  /// TetMesh::region; empty: one layer.
  std::vector<double> layers;
  double refine_x = 0, refine_y = 0, refine_radius = 0, refine_stretch_x = 1.0;
  double fine_size = 0, coarse_size = 0, grade_distance = 0;
  bool half = false;
};

enum class NoseShape { Flat, Hemispherical, Ogive };

/// Body of revolution in its local frame: axis along +z, nose tip at z = 0, base at
/// z = length. Ogive: tangent ogive of calibre-radius-head `crh` (arc radius crh * diameter).
/// Optional inner cavity: a cylinder of `cavity_diameter` from z = cavity_start to cavity_end.
/// `half` keeps only y >= 0.
struct ProjectileSpec {
  double diameter = 0, length = 0;
  NoseShape nose = NoseShape::Flat;
  double crh = 2.0;
  double cavity_diameter = 0, cavity_start = 0, cavity_end = 0;
  double mesh_size = 0;
  bool half = false;
};

/// Nose length: 0 (flat), r (hemisphere) or sqrt(R^2 - (R - r)^2) with R = crh * d (ogive).
inline double noseLength(const ProjectileSpec& s) {
  const double r = 0.5 * s.diameter, big_r = s.crh * s.diameter;
  switch (s.nose) {
    case NoseShape::Flat: return 0.0;
    case NoseShape::Hemispherical: return r;
    case NoseShape::Ogive: return std::sqrt(big_r * big_r - (big_r - r) * (big_r - r));
  }
  return 0.0;
}

/// Mesh quality figures. Shape quality q = 12 (3V)^(2/3) / sum(l^2), 1 for a regular tet.
struct MeshQuality {
  std::size_t nodes = 0, elements = 0;
  double min_quality = 0, mean_quality = 0;
  double min_dihedral_deg = 0;
  double volume = 0;  ///< m^3
};

/// Gmsh meshers (OpenCASCADE geometry, single-threaded Delaunay): the same spec gives the same
/// mesh, bit for bit. Calls are serialised (Gmsh has one global state) and restore the OpenMP
/// thread count that gmsh::initialize() resets to 1. An inconsistent spec or a Gmsh failure
/// throws InputError (with no file).
TetMesh meshPlate(const PlateSpec& spec);
TetMesh meshProjectile(const ProjectileSpec& spec);
/// A physical volume of a Gmsh mesh, by name or by tag; neither: every volume.
struct MshVolume {
  std::string name;
  long long tag = 0;  ///< Gmsh's physical tags are positive
  bool all() const { return name.empty() && tag == 0; }
};

/// Read the tetrahedra of a Gmsh .msh file (ASCII 2.2 or 4.1), those of the physical volume
/// `volume` only when it names one (a body of a mesh with several, e.g. a core and its
/// jacket). Coordinates are multiplied by `scale` (e.g. 1e-3 for a file in mm). Bad files
/// throw InputError naming file and line; a volume that holds no tet, naming the file's
/// physical volumes.
TetMesh readMsh(const std::string& path, double scale = 1.0, const MshVolume& volume = {});
/// Read the tetrahedra of the physical volumes `volumes` (several, e.g. a core and its jacket
/// meshed conformally), region[t] the index of tet t's volume; they keep the nodes they
/// share, so the volumes are tied. Every tet of the file must be in exactly one of them: a tet
/// in none or in two, and a volume that holds no tet, throw InputError naming the file's
/// physical volumes.
TetMesh readMsh(const std::string& path, double scale, const std::vector<MshVolume>& volumes);
MeshQuality meshQuality(const TetMesh& mesh);

/// Signed volume of the tet (a, b, c, d): det[b-a, c-a, d-a] / 6.
inline double tetVolume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

}  // namespace fesph
