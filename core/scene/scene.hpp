// SPDX-License-Identifier: MIT
// Scenes: a TOML file (SI units) describing the simulation, materials, bodies, boundary
// conditions and output. Everything is checked before any work starts; errors name the file,
// line and column and say what was expected.
#pragma once

#include "core/mesh/mesh.hpp"
#include "core/state/model.hpp"
#include "core/state/model_build.hpp"

#include <iosfwd>
#include <string>
#include <variant>
#include <vector>

namespace fesph {

struct MshShape {
  std::string path;  ///< resolved against the scene's folder
  double scale = 1.0;
  MshVolume volume;  ///< the physical volume that is the body (none: every volume)
  /// A body of several physical volumes, one material each (SceneBody::volume_materials),
  /// tied at the nodes they share; empty: `volume`.
  std::vector<MshVolume> volumes;
};

struct SceneBody {
  std::string name;
  std::string material;  ///< material id (its first volume's when it has several)
  /// The material of each volume of a body of several: MshShape::volumes (`materials =
  /// { core = "id", ... }`) or a plate's layers (PlateSpec::layers); empty: the body is of
  /// `material`.
  std::vector<std::string> volume_materials;
  std::vector<std::string> volume_names;  ///< as messages name them: 'core', 7, layer 1
  Discretisation discretisation = Discretisation::Fem;
  bool projectile = false;
  std::variant<PlateSpec, ProjectileSpec, MshShape> shape;
  Placement placement;
  Vec3 velocity = Vec3::Zero();
  int line = 0;  ///< line of its [[bodies]] table in the scene file
};

struct FixedBoundary {
  std::string body;       ///< body name
  std::string where;      ///< "rim" (plate edges) or "box"
  Vec3 box_min = Vec3::Zero(), box_max = Vec3::Zero();  ///< global coordinates, for "box"
  int line = 0;           ///< of its [[boundary]] table in the scene
};

/// The names [output].fields takes: the element series' cell and point arrays.
const std::vector<std::string>& outputFieldNames();
/// "" for a name of outputFieldNames(), else what is wrong with it and what is allowed.
std::string outputFieldError(const std::string& name);

struct OutputSpec {
  std::string folder;                ///< run folder
  double interval = 0;               ///< s between field outputs
  std::vector<std::string> fields;   ///< empty: all
  long history_every = 10;           ///< steps between history rows
  double checkpoint_interval = 0;    ///< s of simulated time between checkpoints; 0: none
  long checkpoints_kept = 2;         ///< the newest checkpoints kept in the run folder
};

/// [reference]: what a scene's results are compared with, residual velocity after each plate
/// (m/s, in the order the projectile meets the plates).
struct ReferenceData {
  std::string source;                   ///< where the numbers come from
  std::vector<double> experiment;       ///< measured; empty: none
  std::vector<std::pair<std::string, std::vector<double>>> published;  ///< label -> values
};

struct Scene {
  std::string path;    ///< the scene file
  std::string text;    ///< the scene as run (overrides and resolution applied), TOML
  std::string source;  ///< the text as read, before the overrides
  std::vector<std::string> overrides;  ///< the --set overrides applied, in order
  std::string material_library;  ///< path of the material library it was read with
  std::string title;
  std::string resolution = "default";  ///< the [resolutions] preset applied
  SolverControls controls;
  SphControls sph;     ///< [sph]: particle parameters
  OutputSpec output;
  bool half = false;   ///< half model cut on y = 0
  std::vector<Material> materials;  ///< the materials the bodies use (overrides applied)
  std::vector<std::string> material_ids;  ///< library id of each entry of `materials`
  std::vector<SceneBody> bodies;
  std::vector<FixedBoundary> fixed;
  std::vector<SymmetryPlane> symmetry;
  std::vector<RigidWall> walls;
  ReferenceData reference;
};

/// Read and check a scene. `overrides` are "dotted.key=value" strings (TOML values) applied
/// before checking, e.g. "simulation.end_time=2e-5" or "bodies.0.velocity=[0,0,-200]".
/// `material_library`: path of the material library; empty means the one beside the scene
/// (scenes/materials.toml found by walking up from the scene's folder).
Scene loadScene(const std::string& path, const std::vector<std::string>& overrides = {},
                const std::string& material_library = "");

/// loadScene of a scene text; `path` names it in messages and resolves relative paths.
Scene loadSceneText(const std::string& text, const std::string& path,
                    const std::vector<std::string>& overrides = {},
                    const std::string& material_library = "");

/// Mesh every body and assemble the model. Writes mesh figures to `log` when given.
Model buildModel(const Scene& scene, std::ostream* log = nullptr);

/// Make `plane` a symmetry plane of the model: the velocity component normal to it is held for
/// the nodes on it (within round-off of the model's size), and the particles see their mirror
/// images across it and are kept on the model's side (docs/sph.md, "Symmetry planes").
void addSymmetryPlane(Model& model, const SymmetryPlane& plane);

}  // namespace fesph
