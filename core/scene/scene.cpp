// SPDX-License-Identifier: MIT
#include "core/scene/scene.hpp"

#include "core/common/number_text.hpp"
#include "core/common/read_file.hpp"
#include "core/common/toml_check.hpp"
#include "core/material/library.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <ostream>
#include <set>
#include <sstream>

namespace fesph {

namespace fs = std::filesystem;
using namespace tomlcheck;

namespace {

// ---- --set overrides ------------------------------------------------------------------

// The parts of a dotted key path ("bodies.0.shape.mesh_size").
std::vector<std::string> pathParts(const std::string& path, const std::string& src, int line,
                                   int col) {
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string p; std::getline(ss, p, '.');) parts.push_back(p);
  if (parts.empty() || std::any_of(parts.begin(), parts.end(), [](auto& p) { return p.empty(); }))
    throw InputError(src, line, col, "'" + path + "' is not a dotted key path");
  return parts;
}

// The table that holds the last part of a dotted path, tables on the way made where missing.
// An array element is named by its index or, for arrays of tables, by the table's `name`
// ("bodies.plate_1.velocity"). `src`, `line`, `col`: where the path comes from, for errors.
toml::table& parentTable(toml::table& root, const std::vector<std::string>& parts,
                         const std::string& path, const std::string& src, int line, int col) {
  toml::node* node = &root;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    const std::string& p = parts[i];
    if (toml::table* t = node->as_table()) {
      node = t->get(p);
      if (!node) node = &t->insert_or_assign(p, toml::table{}).first->second;
    } else if (toml::array* a = node->as_array()) {
      char* end = nullptr;
      const long idx = std::strtol(p.c_str(), &end, 10);
      node = nullptr;
      if (!*end && idx >= 0 && static_cast<std::size_t>(idx) < a->size()) {
        node = a->get(static_cast<std::size_t>(idx));
      } else if (*end) {
        for (auto& item : *a) {
          const toml::table* t = item.as_table();
          if (t && t->get_as<std::string>("name") && **t->get_as<std::string>("name") == p)
            node = &item;
        }
      }
      if (!node)
        throw InputError(src, line, col,
                         "'" + p + "' is neither an index of the array (size " +
                             std::to_string(a->size()) + ") nor the name of one of its tables, on "
                             "the way to " + path);
    } else {
      throw InputError(src, line, col, "'" + p + "' in " + path + " is not a table or an array");
    }
  }
  toml::table* target = node->as_table();
  if (!target)
    throw InputError(src, line, col, "the parent of '" + parts.back() + "' is not a table");
  return *target;
}

// Set the value at a dotted path (see parentTable).
void setAt(toml::table& root, const std::string& path, const toml::node& value,
           const std::string& src, int line, int col) {
  const std::vector<std::string> parts = pathParts(path, src, line, col);
  parentTable(root, parts, path, src, line, col).insert_or_assign(parts.back(), value);
}

void applyOverride(toml::table& root, const std::string& assignment) {
  const std::string src = "--set " + assignment;
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(src, 0, 0, "expected key=value, e.g. simulation.end_time=2e-5");
  const std::string value = assignment.substr(eq + 1);
  toml::table value_doc;
  try {
    value_doc = parseText("v = " + value, src);
  } catch (const InputError&) {  // its column would count the "v = " put in front
    throw InputError(src, 0, 0,
                     "'" + value + "' is not a TOML value: expected a number (5e-6), true or "
                     "false, a string in quotes (\"text\"), or an array ([0, 0, -800])");
  }
  setAt(root, assignment.substr(0, eq), *value_doc.get("v"), src, 0, 0);
}

// A name that goes into file names, column heads and labels as it is: no quoting needed.
bool plainName(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
}

// `text` for a one-line comment: a line break in a path or a --set (a multi-line string)
// would end the comment and leave the rest of it as TOML. Control characters become \xNN.
std::string commentText(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      char code[8];
      std::snprintf(code, sizeof code, "\\x%02x", static_cast<unsigned char>(c));
      out += code;
    } else {
      out += c;
    }
  }
  return out;
}

// `resolution = "NAME"` picks the table [resolutions.NAME] of the scene: dotted key paths and
// the values they get, applied like --set (so a scene carries its own quick, default and fine
// meshes). "default" needs no table.
std::string applyResolution(toml::table& root, const std::string& file) {
  const std::string name = string(root, "resolution", file, "default");
  // The name labels the run in summary.toml and the report's tables, written as it is.
  if (!plainName(name))
    fail(file, where(root, "resolution"),
         "'resolution' must be letters, digits, '_' and '-' (it labels the run), got '" + name +
             "'");
  const toml::table* presets = table(root, "resolutions", file);
  const toml::table* preset = presets ? table(*presets, name, file) : nullptr;
  if (!preset) {
    if (name == "default") return name;
    std::string known;
    if (presets)
      for (auto&& [k, v] : *presets) known += (known.empty() ? "" : ", ") + std::string(k.str());
    fail(file, where(root, "resolution"),
         "unknown resolution '" + name + "' (the scene's [resolutions] has: " +
             (known.empty() ? "none" : known) + ")");
  }
  for (auto&& [k, v] : *preset)
    setAt(root, std::string(k.str()), v, file, static_cast<int>(k.source().begin.line),
          static_cast<int>(k.source().begin.column));
  return name;
}

// The preset `name`'s entries set to the values the scene now holds at their paths: once the
// overrides have been applied over the preset, the scene as run applies its preset again
// when it is read, and must get the same values (a --set of a key the preset sets was undone).
void presetAsRun(toml::table& root, const std::string& name, const std::string& file) {
  toml::table* preset = root["resolutions"][name].as_table();
  if (!preset) return;
  std::vector<std::string> keys;
  for (auto&& [k, v] : *preset) keys.emplace_back(k.str());
  for (const std::string& key : keys) {
    const std::vector<std::string> parts = pathParts(key, file, 0, 0);
    const toml::node* now = parentTable(root, parts, key, file, 0, 0).get(parts.back());
    if (now) preset->insert_or_assign(key, *now);
  }
}

// ---- pieces of the scene ----------------------------------------------------------------

// The scene's folder and its parents, nearest first; `scene` may be a bare file name (its
// folder is then the working one: the parent path of "scene.toml" is empty, and
// fs::absolute throws on an empty path).
std::string findMaterialLibrary(const fs::path& scene) {
  for (fs::path d = fs::absolute(scene).parent_path(); !d.empty(); d = d.parent_path()) {
    const fs::path candidate = d / "materials.toml";
    if (fs::exists(candidate)) return candidate.string();
    const fs::path in_scenes = d / "scenes" / "materials.toml";
    if (fs::exists(in_scenes)) return in_scenes.string();
    if (d == d.parent_path()) break;
  }
  return std::string(FESPH_SOURCE_DIR) + "/scenes/materials.toml";
}

void readSimulation(const toml::table& t, const std::string& file, Scene& sc) {
  allowKeys(t, file,
            {"end_time", "courant", "bulk_linear", "bulk_quadratic", "average_nodal_pressure",
             "anp_element_fraction", "symmetry", "dt_min", "dt_growth"},
            "[simulation]");
  SolverControls& c = sc.controls;
  c.end_time = positive(t, "end_time", file);
  c.courant = positive(t, "courant", file, c.courant);
  if (c.courant > 1.0) fail(file, where(t, "courant"), "'courant' must be in (0, 1]");
  c.bulk_linear = positive(t, "bulk_linear", file, c.bulk_linear, true);
  c.bulk_quadratic = positive(t, "bulk_quadratic", file, c.bulk_quadratic, true);
  c.average_nodal_pressure =
      boolean(t, "average_nodal_pressure", file, c.average_nodal_pressure);
  c.anp_element_fraction = positive(t, "anp_element_fraction", file, c.anp_element_fraction, true);
  if (c.anp_element_fraction > 1)
    fail(file, where(t, "anp_element_fraction"), "'anp_element_fraction' must be in [0, 1]");
  c.dt_min = positive(t, "dt_min", file, c.dt_min);
  c.dt_growth = positive(t, "dt_growth", file, c.dt_growth);
  if (c.dt_growth < 1.0) fail(file, where(t, "dt_growth"), "'dt_growth' must be >= 1");
  sc.half = choice(t, "symmetry", file, {"none", "half"}, std::string("none")) == "half";
  if (sc.half) sc.symmetry.push_back({1, 0.0});
}

void readContact(const toml::table* t, const std::string& file, Scene& sc) {
  if (!t) return;
  allowKeys(*t, file, {"passes", "friction", "depth_tolerance"}, "[contact]");
  ContactControls& c = sc.controls.contact;
  const long passes = integer(*t, "passes", file, c.passes);
  if (passes < 1 || passes > 10) fail(file, where(*t, "passes"), "'passes' must be 1 to 10");
  c.passes = static_cast<int>(passes);
  c.friction = positive(*t, "friction", file, c.friction, true);
  c.depth_tolerance = positive(*t, "depth_tolerance", file, c.depth_tolerance);
}

void readConversion(const toml::table* t, const std::string& file, Scene& sc) {
  if (!t) return;
  allowKeys(*t, file,
            {"mode", "plastic_strain", "min_volume_ratio", "max_volume_ratio", "min_dt_ratio"},
            "[conversion]");
  ConversionControls& c = sc.controls.conversion;
  const std::string mode =
      choice(*t, "mode", file, {"none", "erosion", "sph"}, std::string("none"));
  c.mode = mode == "erosion" ? ConversionMode::Erosion
                             : mode == "sph" ? ConversionMode::Sph : ConversionMode::None;
  c.plastic_strain = positive(*t, "plastic_strain", file, c.plastic_strain);
  c.min_volume_ratio = positive(*t, "min_volume_ratio", file, c.min_volume_ratio);
  c.max_volume_ratio = positive(*t, "max_volume_ratio", file, c.max_volume_ratio);
  if (c.max_volume_ratio <= 1 || c.min_volume_ratio >= 1)
    fail(file, t->source(), "volume ratios must satisfy min_volume_ratio < 1 < max_volume_ratio");
  c.min_dt_ratio = positive(*t, "min_dt_ratio", file, c.min_dt_ratio);
  if (c.min_dt_ratio >= 1) fail(file, where(*t, "min_dt_ratio"), "'min_dt_ratio' must be < 1");
}

void readSph(const toml::table* t, const std::string& file, Scene& sc) {
  if (!t) return;
  allowKeys(*t, file,
            {"kappa", "av_alpha", "av_beta", "artificial_stress", "dt_factor"}, "[sph]");
  SphControls& c = sc.sph;
  c.kappa = positive(*t, "kappa", file, c.kappa);
  if (c.kappa < 0.8 || c.kappa > 2.5) fail(file, where(*t, "kappa"), "'kappa' must be in [0.8, 2.5]");
  c.av_alpha = positive(*t, "av_alpha", file, c.av_alpha, true);
  c.av_beta = positive(*t, "av_beta", file, c.av_beta, true);
  c.artificial_stress = boolean(*t, "artificial_stress", file, c.artificial_stress);
  c.dt_factor = positive(*t, "dt_factor", file, c.dt_factor);
  if (c.dt_factor > 1) fail(file, where(*t, "dt_factor"), "'dt_factor' must be in (0, 1]");
}

// A list of residual velocities, one per plate, each a number >= 0: 0 where the projectile
// stopped in the plate (a shot that perforated only the first plates), and after it.
std::vector<double> velocities(const toml::node& n, const std::string& file, const std::string& what,
                               std::size_t plates) {
  const toml::array* a = n.as_array();
  if (!a) fail(file, n.source(), what + " must be an array of velocities in m/s, one per plate");
  std::vector<double> out;
  for (const toml::node& v : *a) {
    if (!v.is_number() || !(numberValue(v) >= 0) || !std::isfinite(numberValue(v)))
      fail(file, v.source(),
           what + ": expected a velocity >= 0 in m/s (0: the projectile stopped in that plate)");
    if (!out.empty() && out.back() == 0 && numberValue(v) > 0)
      fail(file, v.source(),
           what + ": a velocity after a 0 (the projectile stopped in the plate before)");
    out.push_back(numberValue(v));
  }
  if (out.size() != plates)
    fail(file, n.source(),
         what + " has " + std::to_string(out.size()) + " value" + (out.size() == 1 ? "" : "s") +
             " for " + std::to_string(plates) + " plate" + (plates == 1 ? "" : "s") +
             ": one residual velocity in m/s after each plate");
  return out;
}

void readReference(const toml::table* t, const std::string& file, Scene& sc) {
  if (!t) return;
  allowKeys(*t, file, {"source", "experiment", "published"}, "[reference]");
  std::size_t plates = 0;
  for (const SceneBody& b : sc.bodies) plates += std::holds_alternative<PlateSpec>(b.shape);
  ReferenceData& r = sc.reference;
  r.source = string(*t, "source", file, "");
  if (const toml::node* e = t->get("experiment"))
    r.experiment = velocities(*e, file, "'experiment'", plates);
  if (const toml::table* p = table(*t, "published", file))
    for (auto&& [k, v] : *p)
      r.published.emplace_back(std::string(k.str()),
                               velocities(v, file, "'" + std::string(k.str()) + "'", plates));
}

// runs/NAME, NAME the scene file's name, or its folder's for a scene.toml: the shipped
// scenes are folders holding a scene.toml, and all of them ran into runs/scene, each run
// replacing the one before.
std::string defaultRunFolder(const std::string& file) {
  const fs::path path(file);
  if (path.filename() != "scene.toml") return "runs/" + path.stem().string();
  const std::string folder = fs::absolute(path).parent_path().filename().string();
  return "runs/" + (folder.empty() ? std::string("scene") : folder);
}

void readOutput(const toml::table* t, const std::string& file, Scene& sc) {
  OutputSpec& o = sc.output;
  o.folder = defaultRunFolder(file);
  o.interval = sc.controls.end_time / 20;
  if (!t) return;
  allowKeys(*t, file,
            {"folder", "interval", "fields", "history_every", "checkpoint_interval",
             "checkpoints_kept"},
            "[output]");
  o.folder = string(*t, "folder", file, o.folder);
  o.interval = positive(*t, "interval", file, o.interval);
  o.fields = strings(*t, "fields", file);
  for (std::size_t k = 0; k < o.fields.size(); ++k)
    if (const std::string error = outputFieldError(o.fields[k]); !error.empty())
      fail(file, (*(*t)["fields"].as_array())[k].source(), error);
  o.history_every = integer(*t, "history_every", file, o.history_every);
  if (o.history_every < 1) fail(file, where(*t, "history_every"), "'history_every' must be >= 1");
  o.checkpoint_interval =
      positive(*t, "checkpoint_interval", file, o.checkpoint_interval, true);
  o.checkpoints_kept = integer(*t, "checkpoints_kept", file, o.checkpoints_kept);
  if (o.checkpoints_kept < 1)
    fail(file, where(*t, "checkpoints_kept"), "'checkpoints_kept' must be >= 1");
}

// A mesh size that would need more tetrahedra than any run can hold is a typo (or a unit
// slip), caught here rather than after Gmsh has filled the memory. About 8.5 V / h^3
// tetrahedra fill a volume V at edge length h (a regular tet holds h^3 / (6 sqrt 2)).
constexpr double kMaxTets = 50e6;
double tetEstimate(double volume, double h) { return 6 * std::sqrt(2.0) * volume / (h * h * h); }

void checkMeshCount(double tets, const toml::table& t, const std::string& file) {
  if (tets <= kMaxTets) return;
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "'mesh_size' gives about %.3g tetrahedra for this body (at most %.3g): use a "
                "coarser mesh (the size is in m)",
                tets, kMaxTets);
  fail(file, where(t, "mesh_size"), buf);
}

// `layers = [{ thickness = 3e-3, material = "RHA" }, ...]`: bonded layers from the front face
// back, each of its material (into the body's volumes); the plate is as thick as they are.
void readLayers(const toml::table& t, const std::string& file, PlateSpec& p, SceneBody& b) {
  const toml::node& n = *t.get("layers");
  const toml::array* layers = n.as_array();
  const std::string expected =
      "'layers' must list the plate's layers from its front face back, each { thickness = m, "
      "material = \"id\" }";
  if (!layers || layers->empty()) fail(file, n.source(), expected);
  if (t.contains("thickness"))
    fail(file, where(t, "thickness"),
         "a plate of layers is as thick as its layers together: leave 'thickness' out");
  p.thickness = 0;
  for (std::size_t k = 0; k < layers->size(); ++k) {
    const toml::table* layer = layers->get(k)->as_table();
    if (!layer) fail(file, layers->get(k)->source(), expected);
    allowKeys(*layer, file, {"thickness", "material"}, "plate layer");
    p.layers.push_back(positive(*layer, "thickness", file));
    p.thickness += p.layers.back();
    b.volume_materials.push_back(string(*layer, "material", file));
    b.volume_names.push_back("layer " + std::to_string(k + 1));
  }
}

PlateSpec readPlate(const toml::table& t, const std::string& file, bool half, SceneBody& b) {
  allowKeys(t, file,
            {"type", "size_x", "size_y", "thickness", "layers", "mesh_size", "coarse_size",
             "refine_center", "refine_radius", "refine_stretch_x", "grade_distance"},
            "plate shape");
  PlateSpec p;
  p.size_x = positive(t, "size_x", file);
  p.size_y = positive(t, "size_y", file);
  if (t.contains("layers"))
    readLayers(t, file, p, b);
  else
    p.thickness = positive(t, "thickness", file);
  p.fine_size = positive(t, "mesh_size", file);
  p.coarse_size = positive(t, "coarse_size", file, p.fine_size);
  if (p.coarse_size < p.fine_size)
    fail(file, where(t, "coarse_size"), "'coarse_size' must be >= 'mesh_size'");
  if (const toml::node* n = t.get("refine_center")) {
    const toml::array* a = n->as_array();
    if (!a || a->size() != 2 || !a->get(0)->is_number() || !a->get(1)->is_number() ||
        !std::isfinite(numberValue(*a->get(0))) || !std::isfinite(numberValue(*a->get(1))))
      fail(file, n->source(),
           "'refine_center' must be [x, y] (finite numbers) in the plate's local frame");
    p.refine_x = numberValue(*a->get(0));
    p.refine_y = numberValue(*a->get(1));
  }
  p.refine_radius = positive(t, "refine_radius", file, p.refine_radius, true);
  p.refine_stretch_x = positive(t, "refine_stretch_x", file, p.refine_stretch_x);
  p.grade_distance = positive(t, "grade_distance", file, 0.5 * std::max(p.size_x, p.size_y), true);
  p.half = half;
  const double volume = p.size_x * p.size_y * p.thickness;
  const double r = p.refine_radius * std::max(1.0, p.refine_stretch_x) + p.grade_distance;
  const double fine = p.refine_radius > 0 ? std::min(volume, M_PI * r * r * p.thickness) : volume;
  checkMeshCount(tetEstimate(fine, p.fine_size) + tetEstimate(volume, p.coarse_size), t, file);
  return p;
}

ProjectileSpec readProjectile(const toml::table& t, const std::string& file, bool half) {
  allowKeys(t, file,
            {"type", "diameter", "length", "nose", "crh", "cavity_diameter", "cavity_start",
             "cavity_end", "mesh_size"},
            "projectile shape");
  ProjectileSpec p;
  p.diameter = positive(t, "diameter", file);
  p.length = positive(t, "length", file);
  const std::string nose =
      choice(t, "nose", file, {"flat", "hemispherical", "ogive"}, std::string("flat"));
  p.nose = nose == "flat" ? NoseShape::Flat
                          : nose == "ogive" ? NoseShape::Ogive : NoseShape::Hemispherical;
  p.crh = positive(t, "crh", file, p.crh);
  if (p.nose == NoseShape::Ogive && p.crh < 0.5)
    fail(file, where(t, "crh"), "'crh' of an ogive must be >= 0.5");
  if (!(p.length > noseLength(p))) {  // the nose would be longer than the body
    char what[200];
    std::snprintf(what, sizeof what,
                  "'length' (%.4g mm) must exceed the nose's length (%.4g mm: %s%s on %.4g mm)",
                  1e3 * p.length, 1e3 * noseLength(p), nose.c_str(),
                  p.nose == NoseShape::Ogive ? (" of crh " + shortestText(p.crh)).c_str() : "",
                  1e3 * p.diameter);
    fail(file, where(t, "length"), what);
  }
  p.cavity_diameter = positive(t, "cavity_diameter", file, p.cavity_diameter, true);
  if (p.cavity_diameter > 0) {
    p.cavity_start = positive(t, "cavity_start", file);
    p.cavity_end = positive(t, "cavity_end", file);
    if (p.cavity_diameter >= p.diameter)
      fail(file, where(t, "cavity_diameter"), "'cavity_diameter' must be below 'diameter'");
    if (p.cavity_end <= p.cavity_start || p.cavity_end >= p.length)
      fail(file, where(t, "cavity_end"),
           "the cavity must satisfy cavity_start < cavity_end < length");
  }
  p.mesh_size = positive(t, "mesh_size", file);
  p.half = half;
  checkMeshCount(tetEstimate(0.25 * M_PI * p.diameter * p.diameter * p.length, p.mesh_size), t,
                 file);
  return p;
}

Placement readPlacement(const toml::table& t, const std::string& file) {
  Placement pl;
  pl.translation = vec3(t, "position", file, Vec3::Zero());
  if (const toml::table* r = table(t, "rotation", file)) {
    allowKeys(*r, file, {"axis", "angle_deg"}, "rotation");
    Vec3 axis = vec3(*r, "axis", file);
    if (axis.norm() == 0) fail(file, where(*r, "axis"), "rotation 'axis' must not be zero");
    const double angle = number(*r, "angle_deg", file) * M_PI / 180.0;
    pl.rotation = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  }
  return pl;
}

// `materials = { core = "steel_4340", jacket = "OFHC_copper" }`: the physical volumes of the
// body's msh file (a key is a volume's name, or its tag in digits) and their materials.
void readVolumeMaterials(const toml::table& by_volume, const std::string& file,
                         const toml::table& shape, MshShape& m, SceneBody& b) {
  if (shape.contains("physical"))
    fail(file, where(shape, "physical"),
         "'physical' makes the body one physical volume of one material; with 'materials' "
         "the body is the volumes it names: leave 'physical' out");
  if (by_volume.empty())
    fail(file, by_volume.source(),
         "'materials' must give at least one physical volume its material, e.g. materials = "
         "{ core = \"steel_4340\", jacket = \"OFHC_copper\" }");
  for (auto&& [key, value] : by_volume) {
    const std::string k(key.str());
    if (!value.is_string() || value.as_string()->get().empty())
      fail(file, value.source(),
           "the material of physical volume '" + k + "' must be a material id (a string)");
    MshVolume v;
    const bool digits =
        std::all_of(k.begin(), k.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (digits && k.size() < 18 && std::stoll(k) > 0) v.tag = std::stoll(k);
    else v.name = k;
    m.volumes.push_back(v);
    b.volume_materials.push_back(value.as_string()->get());
    b.volume_names.push_back(v.name.empty() ? k : "'" + k + "'");
  }
}

SceneBody readBody(const toml::table& t, const std::string& file, const Scene& sc) {
  allowKeys(t, file,
            {"name", "material", "materials", "discretisation", "projectile", "velocity",
             "position", "rotation", "shape"},
            "[[bodies]]");
  SceneBody b;
  b.line = static_cast<int>(t.source().begin.line);
  b.name = string(t, "name", file);
  // A body's name names its image files and its history columns: no path, no separator.
  if (!plainName(b.name))
    fail(file, where(t, "name"),
         "'name' must be letters, digits, '_' and '-' (it names image files and history "
         "columns), got '" + b.name + "'");
  const toml::table* by_volume = table(t, "materials", file);
  if (by_volume && t.contains("material"))
    fail(file, where(t, "materials"),
         "a body has 'material' (one for all of it) or 'materials' (one per physical volume of "
         "its msh file), not both");
  b.discretisation = choice(t, "discretisation", file, {"fem", "sph"}, std::string("fem")) == "sph"
                         ? Discretisation::Sph
                         : Discretisation::Fem;
  b.projectile = boolean(t, "projectile", file, false);
  b.velocity = vec3(t, "velocity", file, Vec3::Zero());
  b.placement = readPlacement(t, file);
  if (sc.half) {
    // The symmetry plane y = 0 must stay one: only rotations about y keep it.
    const Mat3& R = b.placement.rotation;
    if (std::abs(R(1, 1) - 1.0) > 1e-12 || std::abs(b.placement.translation.y()) > 0)
      fail(file, where(t, "rotation"),
           "in a half model bodies may only rotate about the y axis and not move along y");
    if (b.velocity.y() != 0)
      fail(file, where(t, "velocity"), "in a half model the velocity must have y = 0");
  }
  const toml::table& shape = *table(t, "shape", file, true);
  const std::string type = choice(shape, "type", file, {"plate", "projectile", "msh"});
  if (type == "plate") {
    b.shape = readPlate(shape, file, sc.half, b);
    if (!b.volume_materials.empty() && (by_volume || t.contains("material")))
      fail(file, where(t, by_volume ? "materials" : "material"),
           "a plate of layers takes each layer's material from its entry in 'layers': leave "
           "'" + std::string(by_volume ? "materials" : "material") + "' out");
  } else if (type == "projectile") {
    b.shape = readProjectile(shape, file, sc.half);
  } else {
    allowKeys(shape, file, {"type", "file", "scale", "physical"}, "msh shape");
    MshShape m;
    m.path = (fs::path(file).parent_path() / string(shape, "file", file)).string();
    m.scale = positive(shape, "scale", file, m.scale);
    // A physical volume of the file, by name or by its (positive) tag.
    if (const toml::node* n = shape.get("physical")) {
      if (n->is_string() && !n->as_string()->get().empty())
        m.volume.name = n->as_string()->get();
      else if (n->is_integer() && n->as_integer()->get() > 0)
        m.volume.tag = n->as_integer()->get();
      else
        fail(file, n->source(),
             "'physical' must be a physical volume's name (a string) or tag (an integer > 0)");
    }
    if (by_volume) readVolumeMaterials(*by_volume, file, shape, m, b);
    if (!fs::exists(m.path)) fail(file, where(shape, "file"), "mesh file not found: " + m.path);
    b.shape = m;
  }
  if (by_volume && b.volume_materials.empty())
    fail(file, where(t, "materials"),
         "'materials' gives each physical volume of an msh shape its material: this body's "
         "shape is a " + type);
  if (b.volume_materials.empty())
    b.material = string(t, "material", file);
  else
    b.material = b.volume_materials.front();
  return b;
}

void readBoundary(const toml::table& t, const std::string& file, Scene& sc,
                  const std::set<std::string>& body_names) {
  const std::string type = choice(t, "type", file, {"fixed", "symmetry", "rigid_wall"});
  if (type == "fixed") {
    allowKeys(t, file, {"type", "body", "where", "min", "max"}, "fixed boundary");
    FixedBoundary f;
    f.line = static_cast<int>(t.source().begin.line);
    f.body = string(t, "body", file);
    if (!body_names.count(f.body))
      fail(file, where(t, "body"), "no body named '" + f.body + "'");
    f.where = choice(t, "where", file, {"rim", "box"});
    if (f.where == "box") {
      f.box_min = vec3(t, "min", file);
      f.box_max = vec3(t, "max", file);
      if ((f.box_max - f.box_min).minCoeff() <= 0)
        fail(file, where(t, "max"), "'max' must exceed 'min' in every component");
    }
    sc.fixed.push_back(f);
  } else if (type == "symmetry") {
    allowKeys(t, file, {"type", "axis", "position"}, "symmetry boundary");
    SymmetryPlane s;
    const std::string axis = choice(t, "axis", file, {"x", "y", "z"});
    s.axis = axis[0] - 'x';
    s.position = number(t, "position", file, 0.0);
    // Mirror images of mirror images: two planes on one axis would make infinitely many.
    for (const SymmetryPlane& other : sc.symmetry)
      if (other.axis == s.axis)
        fail(file, where(t, "axis"),
             "a second symmetry plane normal to " + axis + " (one per axis" +
                 (sc.half ? "; [simulation] symmetry = \"half\" is the plane y = 0)" : ")"));
    sc.symmetry.push_back(s);
  } else {
    allowKeys(t, file, {"type", "point", "normal", "friction"}, "rigid wall");
    RigidWall w;
    w.point = vec3(t, "point", file);
    w.normal = vec3(t, "normal", file);
    if (w.normal.norm() == 0) fail(file, where(t, "normal"), "'normal' must not be zero");
    w.normal.normalize();
    w.friction = positive(t, "friction", file, w.friction, true);
    sc.walls.push_back(w);
  }
}

// Every table of the scene, overrides and preset applied, into `sc`.
void readSceneTables(const toml::table& root, const std::string& file,
                     const std::string& material_library, Scene& sc) {
  allowKeys(root, file,
            {"title", "resolution", "resolutions", "simulation", "output", "contact",
             "conversion", "sph", "materials", "bodies", "boundary", "reference"},
            "the scene");
  sc.title = string(root, "title", file, fs::path(file).stem().string());
  readSimulation(*table(root, "simulation", file, true), file, sc);
  readOutput(table(root, "output", file), file, sc);
  readContact(table(root, "contact", file), file, sc);
  readConversion(table(root, "conversion", file), file, sc);
  readSph(table(root, "sph", file), file, sc);

  const std::string lib_path =
      material_library.empty() ? findMaterialLibrary(file) : material_library;
  const MaterialLibrary lib = MaterialLibrary::load(lib_path);
  sc.material_library = lib_path;
  const toml::table* overrides_tbl = table(root, "materials", file);

  const auto bodies = tables(root, "bodies", file);
  if (bodies.empty()) fail(file, root.source(), "the scene has no [[bodies]]");
  std::set<std::string> names;
  std::vector<std::string> material_ids;
  for (const toml::table* bt : bodies) {
    SceneBody b = readBody(*bt, file, sc);
    if (!names.insert(b.name).second)
      fail(file, where(*bt, "name"), "a body named '" + b.name + "' already exists");
    // A material of the library, or one the scene defines whole under [materials.ID]: a
    // scene then carries its own material and runs the same wherever it is copied.
    const auto use = [&](const std::string& id, const toml::source_region& at) {
      if (!lib.contains(id) && !(overrides_tbl && overrides_tbl->get_as<toml::table>(id))) {
        std::string all;
        for (const auto& known : lib.ids()) all += (all.empty() ? "" : ", ") + known;
        fail(file, at,
             "unknown material '" + id + "': not defined in the scene as [materials." + id +
                 "], and the library " + lib_path + " has only: " + all);
      }
      if (std::find(material_ids.begin(), material_ids.end(), id) == material_ids.end())
        material_ids.push_back(id);
    };
    if (const toml::table* by_volume = bt->get_as<toml::table>("materials"))
      for (auto&& [key, value] : *by_volume) use(value.as_string()->get(), value.source());
    else if (const toml::array* layers = bt->at_path("shape.layers").as_array())
      for (const toml::node& layer : *layers)
        use(string(*layer.as_table(), "material", file), where(*layer.as_table(), "material"));
    else
      use(b.material, where(*bt, "material"));
    sc.bodies.push_back(std::move(b));
  }
  if (overrides_tbl) {
    for (auto&& [k, v] : *overrides_tbl) {
      const std::string id(k.str());
      if (std::find(material_ids.begin(), material_ids.end(), id) == material_ids.end())
        fail(file, k.source(),
             "material '" + id + "' is not used by any body: [materials." + id +
                 "] changes or defines a material for the bodies that name it");
      if (!v.is_table()) fail(file, v.source(), "[materials." + id + "] must be a table");
    }
  }
  for (const std::string& id : material_ids) {
    const toml::table* over = overrides_tbl ? table(*overrides_tbl, id, file) : nullptr;
    const Material base = lib.contains(id) ? lib.get(id) : Material{};  // none: every key needed
    sc.materials.push_back(over ? parseMaterial(*over, file, base, id) : base);
  }
  sc.material_ids = material_ids;

  for (const toml::table* bt : tables(root, "boundary", file)) readBoundary(*bt, file, sc, names);
  readReference(table(root, "reference", file), file, sc);
}

}  // namespace

Scene loadScene(const std::string& path, const std::vector<std::string>& overrides,
                const std::string& material_library) {
  std::string text, why;
  if (!readWholeFile(path, text, why))
    throw InputError(path, 0, 0, "cannot read the scene: " + why);
  return loadSceneText(text, path, overrides, material_library);
}

Scene loadSceneText(const std::string& text, const std::string& path,
                    const std::vector<std::string>& overrides,
                    const std::string& material_library) {
  Scene sc;
  sc.path = path;
  sc.source = text;
  sc.overrides = overrides;
  toml::table root = parseText(sc.source, path);
  const std::string& file = path;
  for (const std::string& o : overrides) applyOverride(root, o);
  // The resolution preset first, then the --set overrides again so that they win over it.
  sc.resolution = applyResolution(root, file);
  // Any preset applied, "default" too when the scene gives it one.
  if (root["resolutions"][sc.resolution].is_table() && !overrides.empty()) {
    for (const std::string& o : overrides) applyOverride(root, o);
    presetAsRun(root, sc.resolution, file);
  }
  // The scene as it runs: overrides and preset applied, every number to round-trip precision.
  std::ostringstream effective;
  effective << "# fesph: the scene " << commentText(path) << " as run (resolution "
            << sc.resolution;
  for (const std::string& o : overrides) effective << "; --set " << commentText(o);
  effective << ")\n" << root << "\n";
  sc.text = effective.str();
  try {
    readSceneTables(root, file, material_library, sc);
  } catch (const InputError& e) {
    // A value from --set has no line in the file: name the --set it came from.
    if (e.line() > 0 || e.file() != file) throw;
    // The key is named before any "; did you mean 'KEY'?": a --set of the key suggested is
    // not the one at fault.
    const std::string named = e.message().substr(0, e.message().find("; "));
    std::string from;
    for (const std::string& o : overrides) {
      const std::string key = o.substr(0, o.find('='));
      const std::string last = key.substr(key.rfind('.') + 1);
      if (named.find("'" + last + "'") != std::string::npos) from += " --set " + o;
    }
    if (from.empty()) throw;
    throw InputError(file, 0, 0, e.message() + " (given by" + from + ")");
  }
  return sc;
}

const std::vector<std::string>& outputFieldNames() {
  static const std::vector<std::string> names = {
      "stress", "pressure", "von_mises", "plastic_strain", "plastic_strain_rate",
      "temperature", "damage", "density", "body", "material", "element_id", "velocity",
      "displacement", "node_id"};
  return names;
}

std::string outputFieldError(const std::string& name) {
  const std::vector<std::string>& known = outputFieldNames();
  if (std::find(known.begin(), known.end(), name) != known.end()) return "";
  std::string allowed;
  for (const std::string& a : known) allowed += (allowed.empty() ? "" : ", ") + a;
  return "unknown output field \"" + name + "\"; allowed: " + allowed;
}

}  // namespace fesph
