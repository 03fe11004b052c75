// SPDX-License-Identifier: MIT
// Meshing the bodies of a checked scene and assembling its Model (the reader is scene.cpp).
#include "core/scene/scene.hpp"

#include "core/common/error.hpp"
#include "core/mesh/untied_parts.hpp"
#include "core/scene/initial_overlap.hpp"
#include "core/sph/particle_body.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <ostream>

namespace fesph {

namespace {

namespace fs = std::filesystem;

TetMesh meshBody(const SceneBody& b, const std::string& scene_path) {
  try {
    if (const auto* p = std::get_if<PlateSpec>(&b.shape)) return meshPlate(*p);
    if (const auto* p = std::get_if<ProjectileSpec>(&b.shape)) return meshProjectile(*p);
  } catch (const InputError& e) {
    // The mesher knows no file: its complaint (a spec the scene reader let through, a Gmsh
    // failure) is put at the body's table in the scene.
    if (!e.file().empty()) throw;
    throw InputError(scene_path, b.line, 0, "body '" + b.name + "': " + e.message());
  }
  const auto& m = std::get<MshShape>(b.shape);
  try {
    return m.volumes.empty() ? readMsh(m.path, m.scale, m.volume)
                             : readMsh(m.path, m.scale, m.volumes);
  } catch (const InputError& e) {
    // A physical volume the file lacks, or one the scene gives no material, is the scene's
    // mistake: said at the body's table.
    if (e.line() != 0 || (m.volume.all() && m.volumes.empty())) throw;
    throw InputError(scene_path, b.line, 0, "body '" + b.name + "': " + e.file() + ": " +
                                                e.message());
  }
}

// An msh body's parts that touch or overlap without sharing nodes (volumes meshed apart) would
// pass through each other, a body having no contact with itself: refused at the body's line.
void checkTied(const Scene& sc, const SceneBody& b, const TetMesh& mesh) {
  const UntiedContact untied = untiedParts(mesh);
  if (untied.faces == 0) return;
  const auto volumeOf = [&](int tet) -> std::string {
    if (mesh.region.empty()) return "";
    return b.volume_names[static_cast<std::size_t>(mesh.region[static_cast<std::size_t>(tet)])];
  };
  const std::string a = volumeOf(untied.tet), c = volumeOf(untied.other);
  char where[160];
  std::snprintf(where, sizeof where, "%zu faces, the first at (%.4g, %.4g, %.4g) mm in the file",
                untied.faces, 1e3 * untied.centre.x(), 1e3 * untied.centre.y(),
                1e3 * untied.centre.z());
  throw InputError(
      sc.path, b.line, 0,
      "body '" + b.name + "': " +
          (a.empty() ? std::string("parts of its mesh") : "its volumes " + a + " and " + c) +
          " touch or overlap without sharing their nodes (" + where +
          "): meshed apart, they are not tied, and a body has no contact with itself, so they "
          "would pass through each other. Mesh them as one (in Gmsh, fragment the volumes: "
          "BooleanFragments) to tie them, or make them two bodies with 'physical' to have "
          "them meet through the contact");
}

// Nodes on the lateral faces of a plate, found in its local frame.
void fixPlateRim(Model& model, int body, const TetMesh& mesh, const PlateSpec& p) {
  const double tol = 1e-6 * std::max(p.size_x, p.size_y);
  const Body& b = model.bodies[body];
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i) {
    const Vec3& x = mesh.nodes[i];
    const bool rim = std::abs(std::abs(x.x()) - 0.5 * p.size_x) < tol ||
                     std::abs(x.y() - 0.5 * p.size_y) < tol ||
                     (!p.half && std::abs(x.y() + 0.5 * p.size_y) < tol);
    if (rim) model.nodes.fix[b.node_begin + i] = 0b111;
  }
}

// How far off a symmetry plane a point still lies on it, relative to the model's size: nodes
// meshed on the plane sit on it to round-off.
double planeTolerance(const Model& model) {
  double extent = 0;
  for (const Vec3& x : model.nodes.x) extent = std::max(extent, x.cwiseAbs().maxCoeff());
  for (const Vec3& x : model.particles.x) extent = std::max(extent, x.cwiseAbs().maxCoeff());
  return 1e-9 * std::max(extent, 1e-3);
}

// A model with a symmetry plane is the part of the full model on one side of it. A body
// meshed whole (a full .msh in a half model) or bodies on both sides would be mirrored onto
// themselves or each other: refused, naming the body and how far it reaches.
void checkOneSide(const Scene& sc, const Model& model, const SymmetryPlane& s) {
  const double tol = planeTolerance(model);
  const char axis = static_cast<char>('x' + s.axis);
  int side_body = -1, side = 0;  // the first body off the plane, and its side
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    const Body& body = model.bodies[b];
    double lo = 0, hi = 0;
    for (std::size_t a = body.node_begin; a < body.node_end; ++a) {
      lo = std::min(lo, model.nodes.x[a][s.axis] - s.position);
      hi = std::max(hi, model.nodes.x[a][s.axis] - s.position);
    }
    for (std::size_t i = 0; i < model.particles.size(); ++i)
      if (model.particles.body[i] == static_cast<int>(b)) {
        lo = std::min(lo, model.particles.x[i][s.axis] - s.position);
        hi = std::max(hi, model.particles.x[i][s.axis] - s.position);
      }
    char reach[128];
    std::snprintf(reach, sizeof reach, "%c = %.4g to %.4g mm", axis, 1e3 * (s.position + lo),
                  1e3 * (s.position + hi));
    char plane[48];
    std::snprintf(plane, sizeof plane, "%c = %.4g mm", axis, 1e3 * s.position);
    const SceneBody& sb = sc.bodies[b];
    if (lo < -tol && hi > tol)
      throw InputError(sc.path, sb.line, 0,
                       "body '" + sb.name + "' lies on both sides of the symmetry plane " + plane +
                           " (" + reach + "): a model with a symmetry plane holds only the " +
                           "part on one side of it, so mesh that part only");
    const int this_side = lo < -tol ? -1 : hi > tol ? 1 : 0;
    if (this_side == 0) continue;
    if (side != 0 && this_side != side) {
      const SceneBody& other = sc.bodies[static_cast<std::size_t>(side_body)];
      throw InputError(sc.path, sb.line, 0,
                       "bodies '" + other.name + "' (line " + std::to_string(other.line) +
                           ") and '" + sb.name + "' lie on opposite sides of the symmetry plane " +
                           plane + " (" + sb.name + ": " + reach +
                           "): a model with a symmetry plane holds only the part on one side");
    }
    if (side == 0) side = this_side, side_body = static_cast<int>(b);
  }
}

// A body's .msh file in mm read as m makes a projectile metres long, and a scale given to a
// file already in m one of microns: both run, to no purpose. Bodies of this tool measure
// from a millimetre (a fragment) to a metre (a large plate).
constexpr double kLargestBody = 2.0, kSmallestBody = 1e-4;  // m, across its longest side

// "12.3 g" or "4.56 kg".
std::string massText(double kg) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g %s", kg < 1 ? 1e3 * kg : kg, kg < 1 ? "g" : "kg");
  return text;
}

// The meshing log's line for a body: its mesh, its size and mass (where a unit slip shows),
// its quality, and for a body of several volumes (physical volumes of a file, a plate's
// layers) each volume's tets, material and mass; the warning for an .msh body of a size no
// body of this tool has. `materials`: as addBody's.
void describeBody(const Scene& sc, const SceneBody& b, const TetMesh& mesh,
                  const std::vector<int>& materials, std::ostream& log) {
  const MeshQuality q = meshQuality(mesh);
  Vec3 lo = mesh.nodes.front(), hi = lo;
  for (const Vec3& x : mesh.nodes) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const Vec3 size = hi - lo;
  std::vector<double> volume_mass(b.volume_materials.size(), 0.0);
  std::vector<std::size_t> volume_tets(b.volume_materials.size(), 0);
  double mass = 0;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& c = mesh.tets[t];
    const double m = sc.materials[static_cast<std::size_t>(tetMaterial(mesh, materials, t))].rho0 *
                     tetVolume(mesh.nodes[c[0]], mesh.nodes[c[1]], mesh.nodes[c[2]],
                               mesh.nodes[c[3]]);
    mass += m;
    if (!mesh.region.empty()) {
      volume_mass[static_cast<std::size_t>(mesh.region[t])] += m;
      ++volume_tets[static_cast<std::size_t>(mesh.region[t])];
    }
  }
  char line[160];
  std::snprintf(line, sizeof line, "%.6g x %.6g x %.6g mm, %s", 1e3 * size.x(), 1e3 * size.y(),
                1e3 * size.z(), massText(mass).c_str());
  log << "  body '" << b.name << "': " << q.nodes << " nodes, " << q.elements << " tets, "
      << line << (sc.symmetry.empty() ? "" : " (its part on one side of the symmetry plane)")
      << ", shape quality min " << q.min_quality << " mean " << q.mean_quality
      << ", min dihedral " << q.min_dihedral_deg << " deg\n";
  for (std::size_t v = 0; v < b.volume_materials.size(); ++v)
    log << "    " << (std::holds_alternative<MshShape>(b.shape) ? "volume " : "")
        << b.volume_names[v] << ": " << volume_tets[v] << " tets of " << b.volume_materials[v]
        << ", " << massText(volume_mass[v]) << "\n";
  const auto* shape = std::get_if<MshShape>(&b.shape);
  const double across = size.maxCoeff();
  if (!shape || (across <= kLargestBody && across >= kSmallestBody)) return;
  char what[320];
  std::snprintf(what, sizeof what,
                "warning: body '%s' measures %.6g mm across (%s at scale %g): the scene is in "
                "m, so a file in mm needs scale = 1e-3, one in m scale = 1 (the default)\n",
                b.name.c_str(), 1e3 * across, fs::path(shape->path).filename().string().c_str(),
                shape->scale);
  log << sc.path << ":" << b.line << ": " << what;
}

// Nodes of `body` held in every direction.
std::size_t heldNodes(const Model& model, int body) {
  const Body& b = model.bodies[body];
  std::size_t held = 0;
  for (std::size_t a = b.node_begin; a < b.node_end; ++a) held += model.nodes.fix[a] == 0b111;
  return held;
}

// A box in the wrong place (a typo, mm for m) held nothing and the plate flew off: a fixed
// boundary that holds no node is refused, naming where the body is; the log gives the count.
// `before`: the body's held nodes before this boundary.
void checkHeld(const Scene& sc, const Model& model, const FixedBoundary& f, int body,
               std::size_t before, std::ostream* log) {
  const std::size_t held = heldNodes(model, body) - before;
  if (held == 0) {
    const auto [lo, hi] = bodyExtent(model, body);
    char what[400];
    const Vec3 l = 1e3 * f.box_min, h = 1e3 * f.box_max, bl = 1e3 * lo, bh = 1e3 * hi;
    std::snprintf(what, sizeof what,
                  "the fixed box from (%.6g, %.6g, %.6g) to (%.6g, %.6g, %.6g) mm holds no node "
                  "of body '%s', which spans (%.6g, %.6g, %.6g) to (%.6g, %.6g, %.6g) mm (min "
                  "and max are in m)",
                  l.x(), l.y(), l.z(), h.x(), h.y(), h.z(), f.body.c_str(), bl.x(), bl.y(),
                  bl.z(), bh.x(), bh.y(), bh.z());
    throw InputError(sc.path, f.line, 0, what);
  }
  if (log)
    *log << "  fixed (" << f.where << "): " << held << " nodes of '" << f.body << "' held\n";
}

}  // namespace

void addSymmetryPlane(Model& model, const SymmetryPlane& s) {
  model.symmetry.push_back(s);
  const double tol = planeTolerance(model);
  for (std::size_t a = 0; a < model.nodes.size(); ++a)
    if (std::abs(model.nodes.x[a][s.axis] - s.position) < tol)
      model.nodes.fix[a] |= static_cast<std::uint8_t>(1u << s.axis);
}

Model buildModel(const Scene& sc, std::ostream* log) {
  Model model;
  model.materials = sc.materials;
  model.controls = sc.controls;
  model.sph.controls = sc.sph;
  model.walls = sc.walls;
  std::vector<TetMesh> meshes;
  for (const SceneBody& b : sc.bodies) {
    TetMesh mesh = meshBody(b, sc.path);
    if (std::holds_alternative<MshShape>(b.shape)) checkTied(sc, b, mesh);
    std::vector<int> mats;  // one per region of the mesh (one region unless several volumes)
    for (const std::string& id :
         b.volume_materials.empty() ? std::vector<std::string>{b.material} : b.volume_materials)
      mats.push_back(static_cast<int>(
          std::find(sc.material_ids.begin(), sc.material_ids.end(), id) -
          sc.material_ids.begin()));
    if (log) describeBody(sc, b, mesh, mats, *log);
    if (b.discretisation == Discretisation::Sph)  // one particle per tet, from the start
      addParticleBody(model, b.name, mesh, mats, b.placement, b.velocity, b.projectile,
                      model.sph.controls.kappa);
    else
      addBody(model, b.name, mesh, mats, b.placement, b.velocity, b.projectile);
    meshes.push_back(std::move(mesh));
  }
  for (const FixedBoundary& f : sc.fixed) {
    const int body = static_cast<int>(
        std::find_if(sc.bodies.begin(), sc.bodies.end(),
                     [&](const SceneBody& b) { return b.name == f.body; }) -
        sc.bodies.begin());
    const Body& b = model.bodies[body];
    // A fixed boundary holds nodes: a body made of particles has none to hold.
    if (sc.bodies[body].discretisation == Discretisation::Sph)
      throw InputError(sc.path, f.line, 0,
                       "a fixed boundary holds nodes of elements, and body '" + f.body +
                           "' is made of particles (discretisation = \"sph\"): it has none");
    const std::size_t before = heldNodes(model, body);
    if (f.where == "rim") {
      const auto* p = std::get_if<PlateSpec>(&sc.bodies[body].shape);
      if (!p) throw InputError(sc.path, f.line, 0, "'where = \"rim\"' needs a plate: " + f.body);
      fixPlateRim(model, body, meshes[body], *p);
    } else {
      for (std::size_t a = b.node_begin; a < b.node_end; ++a) {
        const Vec3& x = model.nodes.x[a];
        if ((x - f.box_min).minCoeff() >= 0 && (f.box_max - x).minCoeff() >= 0)
          model.nodes.fix[a] = 0b111;
      }
    }
    checkHeld(sc, model, f, body, before, log);
  }
  for (const SymmetryPlane& s : sc.symmetry) {
    checkOneSide(sc, model, s);
    addSymmetryPlane(model, s);
  }
  finaliseModel(model);
  if (const auto o = findInitialOverlap(model)) {
    const SceneBody& inner = sc.bodies[static_cast<std::size_t>(o->inner)];
    const SceneBody& outer = sc.bodies[static_cast<std::size_t>(o->outer)];
    const Vec3 mm = 1e3 * o->example;
    char at[96];
    std::snprintf(at, sizeof at, "(%.4g, %.4g, %.4g) mm", mm.x(), mm.y(), mm.z());
    throw InputError(sc.path, inner.line, 0,
                     "bodies '" + outer.name + "' (line " + std::to_string(outer.line) + ") and '" +
                         inner.name + "' overlap at the start: " + std::to_string(o->points) + " " +
                         (inner.discretisation == Discretisation::Sph ? "particles" : "nodes") +
                         " of '" + inner.name + "' lie inside elements of '" + outer.name +
                         "', the first at " + at +
                         "; move them apart (a body's position) so that they at most touch");
  }
  return model;
}

}  // namespace fesph
