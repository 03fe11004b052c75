// SPDX-License-Identifier: MIT
// One list of every stored quantity (transfer() below) serves both directions, so that the
// writer and the reader cannot drift apart. Arrays of small fixed structs are stored as 2D
// datasets of their number type (a Vec3 array is N x 3 doubles); scalars as attributes.
#include "core/io/checkpoint.hpp"

#include "core/common/error.hpp"
#include "core/io/hdf5.hpp"
#include "core/io/replace_file.hpp"
#include "core/io/run_metadata.hpp"
#include "core/sph/sph_forces.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <system_error>
#include <type_traits>

namespace fesph {

namespace fs = std::filesystem;

namespace {

constexpr const char* kFormat = "fesph checkpoint";
// Bump with every change of what transfer() stores: an older file then gets a clear error.
// 2: the SPH Verlet skin and last step's pair list and gradients.
// 3: the pairs' stabilisation forces (pair_stab), looked up by the next step.
// 4: what of the projectile got through each plate (PlateCrossing::through_*).
// 5: the symmetry planes.
// 6: the particles' renumbering: SphControls::order_interval and Particles::id.
// 7: no pair_grad_prev (scratch of one step; older files hold it and the reader skips it).
// 8: no neighbour_last_offset, neighbour_last_index, pair_grad_last (the same: skipped).
// 9: no nodal_volume, nodal_volume0 (read by nothing since the element pass takes each node's
//    ratio in their place, before it reads it: skipped).
// 10: no v_node_free, v_particle_free (each step writes them before it reads them; a model
//    not yet stepped has none, and its checkpoint failed the length check): older files hold
//    them and the reader skips them.
// 11: the SPH snapshots' volume rate (SphSnapshot::volume_rate), from which the next step
//    predicts its volumes; older files read it as 0 (one step weighted by V^{n-1}).
// 12: the history's last row (RunProgress::history_last_row); older files leave it empty and
//    their restart does not check the folder's history against it.
// 13: the energy budget's step (EnergyBudget::step), which labels the history's rows; older
//     files take the step before the model's.
// 14: the plate crossings of every projectile (RunProgress::crossings), a group each; older
//     files hold the scene's first projectile's only, in the crossings group itself.
constexpr std::int64_t kFormatVersion = 14;
// Format 2 is still read: its pair_stab is recomputed (restorePairStabilisation).
constexpr std::int64_t kOldestReadable = 2;

// How an array element is laid out: `cols` numbers of type `Base`, contiguous.
template <class T, class = void> struct Layout;
template <class T> struct Layout<T, std::enable_if_t<std::is_arithmetic_v<T>>> {
  using Base = T;
  static constexpr std::size_t cols = 1;
};
template <class T> struct Layout<T, std::enable_if_t<std::is_enum_v<T>>> {
  using Base = std::underlying_type_t<T>;
  static constexpr std::size_t cols = 1;
};
template <> struct Layout<Vec3> { using Base = double; static constexpr std::size_t cols = 3; };
template <> struct Layout<Mat3> { using Base = double; static constexpr std::size_t cols = 9; };
template <> struct Layout<PointState> {
  using Base = double;
  static constexpr std::size_t cols = 12;
};
template <class T, std::size_t N> struct Layout<std::array<T, N>> {
  using Base = T;
  static constexpr std::size_t cols = N;
};
template <> struct Layout<std::pair<int, int>> {
  using Base = int;
  static constexpr std::size_t cols = 2;
};
template <> struct Layout<FaceRecord> { using Base = int; static constexpr std::size_t cols = 6; };
template <> struct Layout<ExteriorFace> {
  using Base = int;
  static constexpr std::size_t cols = 6;
};

// The casts to Base* below rely on these layouts having no padding.
template <class T> constexpr bool packed() {
  return sizeof(T) == Layout<T>::cols * sizeof(typename Layout<T>::Base) &&
         std::is_standard_layout_v<typename Layout<T>::Base>;
}
static_assert(packed<Vec3>() && packed<Mat3>() && packed<PointState>() &&
              packed<std::array<int, 4>>() && packed<FaceRecord>() && packed<ExteriorFace>() &&
              packed<std::pair<int, int>>() && packed<ElemStatus>());

// A field added to the state must be added to transfer() below (or named as scratch there):
// these sizes, the sums of the fields transfer() knows, make the build say so.
constexpr std::size_t kVec = sizeof(std::vector<int>);
#define FESPH_CHECKPOINT_FIELDS(T, size)                                                   \
  static_assert(sizeof(T) == (size), #T " changed: store the new field in the checkpoint " \
                                        "(transfer() in core/io/checkpoint.cpp)")
FESPH_CHECKPOINT_FIELDS(Nodes, 7 * kVec);
FESPH_CHECKPOINT_FIELDS(Elements, 14 * kVec + 2 * kVec + sizeof(long) /* scratch */);
FESPH_CHECKPOINT_FIELDS(Particles, 15 * kVec);
FESPH_CHECKPOINT_FIELDS(SphSnapshot, 11 * kVec);
FESPH_CHECKPOINT_FIELDS(SphWorkspace, sizeof(SphControls) + sizeof(NeighbourSearch) +
                                          2 * sizeof(NeighbourList) + 2 * sizeof(SphSnapshot) +
                                          12 * kVec + 5 * kVec /* scratch */);
FESPH_CHECKPOINT_FIELDS(EnergyBudget, 15 * sizeof(double) + sizeof(long));
FESPH_CHECKPOINT_FIELDS(ConversionStats, 4 * sizeof(long) + sizeof(double));
FESPH_CHECKPOINT_FIELDS(SolverControls, sizeof(ContactControls) + sizeof(ConversionControls) +
                                            8 * sizeof(double));
FESPH_CHECKPOINT_FIELDS(ContactControls, 3 * sizeof(double));
FESPH_CHECKPOINT_FIELDS(ConversionControls, 5 * sizeof(double));
FESPH_CHECKPOINT_FIELDS(SphControls, 11 * sizeof(double));
FESPH_CHECKPOINT_FIELDS(Material, 3 * sizeof(std::string) + 27 * sizeof(double));
FESPH_CHECKPOINT_FIELDS(Body, sizeof(std::string) + 2 * sizeof(int) + sizeof(double) +
                                  4 * sizeof(std::size_t));
FESPH_CHECKPOINT_FIELDS(Model, sizeof(Nodes) + sizeof(Elements) + sizeof(Particles) +
                                   4 * kVec + sizeof(Surfaces) + sizeof(SphWorkspace) +
                                   sizeof(SolverControls) + sizeof(EnergyBudget) +
                                   sizeof(ConversionStats) + 3 * kVec +
                                   3 * kVec /* scratch */ + 2 * sizeof(double) +
                                   sizeof(long) + sizeof(std::string) + sizeof(PhaseTimes));
#undef FESPH_CHECKPOINT_FIELDS

// ---- the two directions ---------------------------------------------------------------

class Writer {
 public:
  static constexpr bool reading = false;
  const std::int64_t version = kFormatVersion;
  explicit Writer(h5::Handle root) { stack_.push_back(std::move(root)); }
  void enter(const std::string& name) { stack_.push_back(h5::createGroup(top(), name)); }
  void leave() { stack_.pop_back(); }

  template <class T> void array(const std::string& name, std::vector<T>& v) {
    using L = Layout<T>;
    h5::writeArray(top(), name, h5::nativeType<typename L::Base>(), v.data(), v.size(), L::cols);
  }
  void value(const std::string& name, std::string& s) { h5::writeAttribute(top(), name, s); }
  void text(const std::string& name, std::string& s) { h5::writeText(top(), name, s); }
  void value(const std::string& name, double& x) { h5::writeAttribute(top(), name, x); }
  template <class T> std::enable_if_t<std::is_integral_v<T> || std::is_enum_v<T>>
  value(const std::string& name, T& x) {
    h5::writeAttribute(top(), name, static_cast<std::int64_t>(x));
  }
  void value(const std::string& name, Vec3& x) {
    std::vector<Vec3> one{x};
    array(name, one);
  }
  /// Number of entries of a list of groups (materials, bodies, walls).
  std::size_t count(const std::string& name, std::size_t n) {
    h5::writeAttribute(top(), name, static_cast<std::int64_t>(n));
    return n;
  }

 private:
  const h5::Handle& top() const { return stack_.back(); }
  std::vector<h5::Handle> stack_;
};

class Reader {
 public:
  static constexpr bool reading = true;
  const std::int64_t version;  ///< of the file
  Reader(h5::Handle root, std::string path, std::int64_t file_version)
      : version(file_version), path_(std::move(path)) {
    stack_.push_back(std::move(root));
  }
  void enter(const std::string& name) { stack_.push_back(h5::openGroup(top(), name)); }
  void leave() { stack_.pop_back(); }

  template <class T> void array(const std::string& name, std::vector<T>& v) {
    using L = Layout<T>;
    const auto [rows, cols] = h5::arrayShape(top(), name);
    if (cols != L::cols)
      throw RunError(path_ + ": dataset " + name + " has " + std::to_string(cols) +
                     " columns, expected " + std::to_string(L::cols));
    v.resize(rows);
    h5::readArray(top(), name, h5::nativeType<typename L::Base>(), v.data());
  }
  void value(const std::string& name, std::string& s) { s = h5::readStringAttribute(top(), name); }
  void text(const std::string& name, std::string& s) { s = h5::readText(top(), name); }
  void value(const std::string& name, double& x) { x = h5::readDoubleAttribute(top(), name); }
  template <class T> std::enable_if_t<std::is_integral_v<T> || std::is_enum_v<T>>
  value(const std::string& name, T& x) {
    x = static_cast<T>(h5::readIntAttribute(top(), name));
  }
  void value(const std::string& name, Vec3& x) {
    std::vector<Vec3> one;
    array(name, one);
    if (one.size() != 1) throw RunError(path_ + ": " + name + " is not one vector");
    x = one[0];
  }
  std::size_t count(const std::string& name, std::size_t) {
    const std::int64_t n = h5::readIntAttribute(top(), name);
    if (n < 0 || n > 1000000) throw RunError(path_ + ": bad count " + name);
    return static_cast<std::size_t>(n);
  }

 private:
  const h5::Handle& top() const { return stack_.back(); }
  std::vector<h5::Handle> stack_;
  std::string path_;
};

// vector<vector<int>> as compressed rows.
template <class Ar> void nested(Ar& ar, const std::string& name, std::vector<std::vector<int>>& v) {
  std::vector<std::size_t> offset{0};
  std::vector<int> flat;
  for (const auto& row : v) {
    flat.insert(flat.end(), row.begin(), row.end());
    offset.push_back(flat.size());
  }
  ar.array(name + "_offset", offset);
  ar.array(name, flat);
  if (!Ar::reading) return;
  if (offset.empty() || offset.front() != 0 || offset.back() != flat.size() ||
      !std::is_sorted(offset.begin(), offset.end()))
    throw RunError("checkpoint: bad row offsets of " + name);
  v.assign(offset.size() - 1, {});
  for (std::size_t r = 0; r + 1 < offset.size(); ++r)
    v[r].assign(flat.begin() + static_cast<long>(offset[r]),
                flat.begin() + static_cast<long>(offset[r + 1]));
}

template <class Ar> void transfer(Ar& ar, Material& m) {
  ar.value("name", m.name);
  ar.value("source", m.source);
  ar.value("status", m.status);
  const std::pair<const char*, double*> numbers[] = {
      {"rho0", &m.rho0}, {"E", &m.E}, {"nu", &m.nu}, {"G", &m.G}, {"K", &m.K}, {"cp", &m.cp},
      {"T_room", &m.T_room}, {"T_melt", &m.T_melt}, {"taylor_quinney", &m.taylor_quinney},
      {"A", &m.A}, {"B", &m.B}, {"n", &m.n}, {"C", &m.C}, {"m", &m.m},
      {"eps_dot0", &m.eps_dot0}, {"D1", &m.D1}, {"D2", &m.D2}, {"D3", &m.D3}, {"D4", &m.D4},
      {"D5", &m.D5}, {"c0", &m.c0}, {"s", &m.s}, {"gamma0", &m.gamma0},
      {"erosion_strain", &m.erosion_strain}};
  for (auto [key, x] : numbers) ar.value(key, *x);
  ar.value("strength", m.strength);
  ar.value("damage", m.damage);
  ar.value("eos", m.eos);
}

template <class Ar> void transfer(Ar& ar, SolverControls& c, SphControls& s) {
  ar.enter("controls");
  ar.value("contact_passes", c.contact.passes);
  ar.value("contact_friction", c.contact.friction);
  ar.value("contact_depth_tolerance", c.contact.depth_tolerance);
  ar.value("conversion_mode", c.conversion.mode);
  ar.value("conversion_plastic_strain", c.conversion.plastic_strain);
  ar.value("conversion_min_volume_ratio", c.conversion.min_volume_ratio);
  ar.value("conversion_max_volume_ratio", c.conversion.max_volume_ratio);
  ar.value("conversion_min_dt_ratio", c.conversion.min_dt_ratio);
  ar.value("end_time", c.end_time);
  ar.value("courant", c.courant);
  ar.value("bulk_linear", c.bulk_linear);
  ar.value("bulk_quadratic", c.bulk_quadratic);
  ar.value("average_nodal_pressure", c.average_nodal_pressure);
  ar.value("anp_element_fraction", c.anp_element_fraction);
  ar.value("dt_growth", c.dt_growth);
  ar.value("dt_min", c.dt_min);
  ar.value("sph_kappa", s.kappa);
  ar.value("sph_av_alpha", s.av_alpha);
  ar.value("sph_av_beta", s.av_beta);
  ar.value("sph_artificial_stress", s.artificial_stress);
  ar.value("sph_as_epsilon", s.as_epsilon);
  ar.value("sph_max_condition", s.max_condition);
  ar.value("sph_min_neighbours", s.min_neighbours);
  ar.value("sph_as_exponent", s.as_exponent);
  ar.value("sph_contact_passes", s.contact_passes);
  ar.value("sph_dt_factor", s.dt_factor);
  ar.value("sph_verlet_skin", s.verlet_skin);
  if (ar.version >= 6) ar.value("sph_order_interval", s.order_interval);  // else the default
  ar.leave();
}

template <class Ar> void transfer(Ar& ar, SphSnapshot& s) {
  ar.array("x", s.x);
  ar.array("v", s.v);
  ar.array("h", s.h);
  ar.array("V", s.V);
  if (ar.version >= 11) ar.array("volume_rate", s.volume_rate);
  else if (Ar::reading) s.volume_rate.assign(s.x.size(), 0.0);
  ar.array("rho", s.rho);
  ar.array("c", s.c);
  ar.array("d", s.d);
  ar.array("B", s.B);
  ar.array("R", s.R);
  ar.array("tensile", s.tensile);
}

// Everything of the Model that outlives a step. Scratch that every step rebuilds before
// reading it (contact candidates and buffers, the neighbour search's grids) is left out.
template <class Ar> void transfer(Ar& ar, Model& m) {
  ar.enter("nodes");
  Nodes& nd = m.nodes;
  ar.array("x", nd.x);
  ar.array("x0", nd.x0);
  ar.array("v", nd.v);
  ar.array("f", nd.f);
  ar.array("m", nd.m);
  ar.array("body", nd.body);
  ar.array("fix", nd.fix);
  ar.leave();

  ar.enter("elements");
  Elements& el = m.elems;
  ar.array("conn", el.conn);
  ar.array("body", el.body);
  ar.array("material", el.material);
  ar.array("V0", el.V0);
  ar.array("V", el.V);
  ar.array("dV", el.dV);
  ar.array("rho", el.rho);
  ar.array("q", el.q);
  ar.array("div_v", el.div_v);
  ar.array("dt", el.dt);
  ar.array("len", el.len);
  ar.array("len0", el.len0);
  ar.array("state", el.state);
  ar.array("status", el.status);
  ar.leave();

  ar.enter("particles");
  Particles& pa = m.particles;
  ar.array("x", pa.x);
  ar.array("v", pa.v);
  ar.array("f", pa.f);
  ar.array("m", pa.m);
  ar.array("V", pa.V);
  ar.array("rho", pa.rho);
  ar.array("h", pa.h);
  ar.array("d0", pa.d0);
  ar.array("dt", pa.dt);
  ar.array("state", pa.state);
  ar.array("body", pa.body);
  ar.array("material", pa.material);
  ar.array("parent", pa.parent);
  if (ar.version >= 6) {
    ar.array("id", pa.id);
  } else if (Ar::reading) {  // never renumbered before format 6: the index is the identity
    pa.id.resize(pa.x.size());
    std::iota(pa.id.begin(), pa.id.end(), 0);
  }
  std::vector<std::array<int, 3>> tie_face(pa.tie.size());
  std::vector<Vec3> tie_bary(pa.tie.size());
  for (std::size_t i = 0; i < pa.tie.size(); ++i)
    tie_face[i] = pa.tie[i].face, tie_bary[i] = pa.tie[i].bary;
  ar.array("tie_face", tie_face);
  ar.array("tie_bary", tie_bary);
  if (Ar::reading) {
    if (tie_bary.size() != tie_face.size()) throw RunError("checkpoint: tie arrays differ");
    pa.tie.resize(tie_face.size());
    for (std::size_t i = 0; i < pa.tie.size(); ++i)
      pa.tie[i].face = tie_face[i], pa.tie[i].bary = tie_bary[i];
  }
  ar.leave();

  ar.enter("materials");
  m.materials.resize(ar.count("count", m.materials.size()));
  for (std::size_t k = 0; k < m.materials.size(); ++k) {
    ar.enter(std::to_string(k));
    transfer(ar, m.materials[k]);
    ar.leave();
  }
  ar.leave();

  ar.enter("bodies");
  m.bodies.resize(ar.count("count", m.bodies.size()));
  for (std::size_t k = 0; k < m.bodies.size(); ++k) {
    Body& b = m.bodies[k];
    ar.enter(std::to_string(k));
    ar.value("name", b.name);
    ar.value("material", b.material);
    ar.value("discretisation", b.discretisation);
    ar.value("is_projectile", b.is_projectile);
    ar.value("node_begin", b.node_begin);
    ar.value("node_end", b.node_end);
    ar.value("elem_begin", b.elem_begin);
    ar.value("elem_end", b.elem_end);
    ar.leave();
  }
  ar.leave();

  ar.enter("walls");
  m.walls.resize(ar.count("count", m.walls.size()));
  for (std::size_t k = 0; k < m.walls.size(); ++k) {
    ar.enter(std::to_string(k));
    ar.value("point", m.walls[k].point);
    ar.value("normal", m.walls[k].normal);
    ar.value("friction", m.walls[k].friction);
    ar.leave();
  }
  ar.leave();

  if (ar.version >= 5) {  // format 4 has none: the restart takes the scene's
    ar.enter("symmetry");
    m.symmetry.resize(ar.count("count", m.symmetry.size()));
    for (std::size_t k = 0; k < m.symmetry.size(); ++k) {
      ar.enter(std::to_string(k));
      ar.value("axis", m.symmetry[k].axis);
      ar.value("position", m.symmetry[k].position);
      ar.leave();
    }
    ar.leave();
  }

  ar.enter("surfaces");
  Surfaces& s = m.surfaces;
  ar.array("table", s.table);
  ar.array("elem_faces", s.elem_faces);
  ar.array("exterior", s.exterior);
  nested(ar, "slave_nodes", s.slave_nodes);
  ar.array("node_face_count", s.node_face_count);
  ar.array("node_slot", s.node_slot);
  ar.leave();

  ar.enter("sph");
  SphWorkspace& ws = m.sph;
  ar.array("neighbour_offset", ws.neighbours.offset);
  ar.array("neighbour_index", ws.neighbours.index);
  ar.array("pair_grad", ws.pair_grad);
  // The last step's list and gradients (neighbours_last, pair_grad_last), pair_stab_last,
  // pair_last_slot and internal_energy are scratch: the next step swaps the current list,
  // gradients and pair_stab into the first three and writes the others before reading them
  // (formats 2-7 hold the first three; the reader skips them). Format 2 lacks pair_stab:
  // readCheckpoint recomputes it. The mirror images (mirrors) are scratch: each step builds
  // them afresh.
  if (ar.version >= 3) ar.array("pair_stab", ws.pair_stab);
  ar.enter("current");
  transfer(ar, ws.current);
  ar.leave();
  ar.enter("previous");
  transfer(ar, ws.previous);
  ar.leave();
  ar.array("corrected", ws.corrected);
  ar.array("velocity_grad", ws.velocity_grad);
  ar.array("velocity_grad_prev", ws.velocity_grad_prev);
  ar.array("stress_b", ws.stress_b);
  ar.array("plastic_work", ws.plastic_work);
  ar.array("av_work", ws.av_work);
  ar.array("contact_radius", ws.contact_radius);
  ar.array("contact_spacing", ws.contact_spacing);
  ar.array("contact_pairs", ws.contact_pairs);
  ar.leave();

  transfer(ar, m.controls, m.sph.controls);

  ar.enter("energy");
  EnergyBudget& en = m.energy;
  const std::pair<const char*, double*> terms[] = {
      {"kinetic", &en.kinetic}, {"internal", &en.internal},
      {"bulk_viscosity", &en.bulk_viscosity}, {"artificial_viscosity", &en.artificial_viscosity},
      {"plastic_work", &en.plastic_work}, {"contact", &en.contact},
      {"contact_through_half", &en.contact_through_half}, {"eroded", &en.eroded},
      {"conversion", &en.conversion}, {"initial", &en.initial},
      {"kinetic_half", &en.kinetic_half}, {"time", &en.time}};
  for (auto [key, x] : terms) ar.value(key, *x);
  ar.value("momentum", en.momentum);
  if (ar.version >= 13) ar.value("step", en.step);
  ar.leave();

  ar.enter("conversion");
  ar.value("eroded", m.conversion.eroded);
  ar.value("converted", m.conversion.converted);
  ar.value("by_damage", m.conversion.by_damage);
  ar.value("by_safety", m.conversion.by_safety);
  ar.value("eroded_mass", m.conversion.eroded_mass);
  ar.leave();

  ar.enter("scratch");
  ar.array("node_corner_offset", m.node_corner_offset);
  ar.array("node_corners", m.node_corners);
  std::vector<std::array<double, 12>> corner_force(m.corner_force.size());
  static_assert(sizeof(corner_force[0]) == sizeof(m.corner_force[0]));
  std::copy_n(reinterpret_cast<const char*>(m.corner_force.data()),
              m.corner_force.size() * sizeof(m.corner_force[0]),
              reinterpret_cast<char*>(corner_force.data()));
  ar.array("corner_force", corner_force);
  if (Ar::reading) {
    m.corner_force.resize(corner_force.size());
    std::copy_n(reinterpret_cast<const char*>(corner_force.data()),
                corner_force.size() * sizeof(corner_force[0]),
                reinterpret_cast<char*>(m.corner_force.data()));
  }
  ar.leave();

  ar.value("time", m.time);
  ar.value("dt", m.dt);
  ar.value("step", m.step);
  ar.value("dt_limiter", m.dt_limiter);
  // Before format 13: the budget is the one the last step closed, at t^(step - 1).
  if (Ar::reading && ar.version < 13) m.energy.step = std::max(0L, m.step - 1);
}

// One projectile's residual-velocity tracking: its body and its plates.
template <class Ar> void transfer(Ar& ar, CrossingsRecord& c) {
  ar.value("projectile", c.projectile);
  c.plates.resize(ar.count("count", c.plates.size()));
  for (std::size_t k = 0; k < c.plates.size(); ++k) {
    PlateCrossing& p = c.plates[k];
    ar.enter(std::to_string(k));
    ar.value("body", p.body);
    ar.value("name", p.name);
    ar.value("normal", p.normal);
    ar.value("front", p.front);
    ar.value("velocity", p.velocity);
    const std::pair<const char*, double*> numbers[] = {
        {"thickness", &p.thickness}, {"measure_depth", &p.measure_depth},
        {"t_contact", &p.t_contact}, {"t_measured", &p.t_measured}, {"speed", &p.speed},
        {"mass_fraction", &p.mass_fraction}};
    for (auto [key, x] : numbers) ar.value(key, *x);
    if (ar.version >= 4) {  // format 3 leaves them unknown (NaN)
      ar.value("through_velocity", p.through_velocity);
      ar.value("through_mass_fraction", p.through_mass_fraction);
    }
    ar.leave();
  }
}

template <class Ar> void transfer(Ar& ar, RunProgress& r) {
  ar.enter("run");
  ar.text("scene_text", r.scene_text);
  std::string overrides;  // one a line (a command-line override is one line)
  for (const std::string& o : r.overrides) overrides += o + '\n';
  ar.text("overrides", overrides);
  if (Ar::reading) {
    r.overrides.clear();
    for (std::size_t at = 0, end; (end = overrides.find('\n', at)) != std::string::npos;
         at = end + 1)
      r.overrides.push_back(overrides.substr(at, end - at));
  }
  ar.value("scene_path", r.scene_path);
  ar.value("material_library", r.material_library);
  ar.value("series_outputs", r.series_outputs);
  ar.value("output_index", r.output_index);
  ar.value("next_output", r.next_output);
  ar.value("next_checkpoint", r.next_checkpoint);
  ar.value("history_rows", r.history_rows);
  if (ar.version >= 12) ar.value("history_last_row", r.history_last_row);
  ar.enter("crossings");
  if (ar.version >= 14) {
    r.crossings.resize(ar.count("projectiles", r.crossings.size()));
    for (std::size_t s = 0; s < r.crossings.size(); ++s) {
      ar.enter("projectile_" + std::to_string(s));
      transfer(ar, r.crossings[s]);
      ar.leave();
    }
  } else {  // the scene's first projectile's, or none (-1)
    r.crossings.resize(1);
    transfer(ar, r.crossings[0]);
    if (r.crossings[0].projectile < 0) r.crossings.clear();
  }
  ar.leave();
  ar.leave();
}

// The arrays must fit together before step() may index with them.
void checkConsistent(const Model& m, const RunProgress& run, const std::string& path,
                     bool has_pair_stab) {
  auto fail = [&](const std::string& what) {
    throw RunError(path + ": inconsistent checkpoint: " + what);
  };
  const std::size_t nn = m.nodes.size(), ne = m.elems.size(), np = m.particles.size();
  const std::size_t nb = m.bodies.size(), nm = m.materials.size();
  const Nodes& nd = m.nodes;
  for (std::size_t n : {nd.x0.size(), nd.v.size(), nd.f.size(), nd.m.size(), nd.body.size(),
                        nd.fix.size(), m.surfaces.node_face_count.size(),
                        m.surfaces.node_slot.size()})
    if (n != nn) fail("node arrays of different lengths");
  const Elements& el = m.elems;
  for (std::size_t n : {el.body.size(), el.material.size(), el.V0.size(), el.V.size(),
                        el.dV.size(), el.rho.size(), el.q.size(), el.div_v.size(), el.dt.size(),
                        el.len.size(), el.len0.size(), el.state.size(), el.status.size(),
                        m.corner_force.size(), m.surfaces.elem_faces.size()})
    if (n != ne) fail("element arrays of different lengths");
  const Particles& pa = m.particles;
  for (std::size_t n : {pa.v.size(), pa.f.size(), pa.m.size(), pa.V.size(), pa.rho.size(),
                        pa.h.size(), pa.d0.size(), pa.dt.size(), pa.state.size(),
                        pa.body.size(), pa.material.size(), pa.parent.size(), pa.tie.size(),
                        pa.id.size()})
    if (n != np) fail("particle arrays of different lengths");
  if (nb == 0) fail("no bodies");
  for (std::size_t a = 0; a < nn; ++a)
    if (nd.body[a] < 0 || static_cast<std::size_t>(nd.body[a]) >= nb) fail("node body");
  for (std::size_t e = 0; e < ne; ++e) {
    for (int c : el.conn[e])
      if (c < 0 || static_cast<std::size_t>(c) >= nn) fail("element connectivity");
    if (el.body[e] < 0 || static_cast<std::size_t>(el.body[e]) >= nb) fail("element body");
    if (el.material[e] < 0 || static_cast<std::size_t>(el.material[e]) >= nm)
      fail("element material");
    if (static_cast<int>(el.status[e]) > 2) fail("element status");
  }
  for (std::size_t i = 0; i < np; ++i) {
    if (pa.body[i] < 0 || static_cast<std::size_t>(pa.body[i]) >= nb) fail("particle body");
    if (pa.material[i] < 0 || static_cast<std::size_t>(pa.material[i]) >= nm)
      fail("particle material");
    for (int c : pa.tie[i].face)
      if (c >= static_cast<int>(nn) || (c < 0 && pa.tie[i].active())) fail("particle tie");
  }
  for (const Body& b : m.bodies)
    if (b.node_begin > b.node_end || b.node_end > nn || b.elem_begin > b.elem_end ||
        b.elem_end > ne || b.material < 0 || static_cast<std::size_t>(b.material) >= nm)
      fail("body ranges");
  if (m.node_corner_offset.size() != nn + 1 || m.node_corner_offset.back() != m.node_corners.size())
    fail("node corner lists");
  for (std::uint32_t c : m.node_corners)
    if (c / 4 >= ne) fail("node corner lists");
  const Surfaces& s = m.surfaces;
  for (const FaceRecord& f : s.table)
    for (int x : f.key)
      if (x < 0 || static_cast<std::size_t>(x) >= nn) fail("face table");
  for (const ExteriorFace& f : s.exterior) {
    for (int x : f.node)
      if (x < 0 || static_cast<std::size_t>(x) >= nn) fail("exterior faces");
    if (f.elem < 0 || static_cast<std::size_t>(f.elem) >= ne || f.body < 0 ||
        static_cast<std::size_t>(f.body) >= nb || f.face < 0 ||
        static_cast<std::size_t>(f.face) >= s.table.size())
      fail("exterior faces");
  }
  for (const auto& row : s.slave_nodes)
    for (int x : row)
      if (x < 0 || static_cast<std::size_t>(x) >= nn) fail("slave nodes");
  const NeighbourList& nl = m.sph.neighbours;
  if (!nl.offset.empty() && nl.offset.back() != nl.index.size()) fail("neighbour list");
  for (int j : nl.index)
    if (j < 0 || static_cast<std::size_t>(j) >= np) fail("neighbour list");
  if (nl.offset.size() > np + 1 || m.sph.pair_grad.size() != nl.index.size() ||
      m.sph.current.size() < nl.offset.size() - (nl.offset.empty() ? 0 : 1))
    fail("neighbour list");
  if (has_pair_stab && m.sph.pair_stab.size() != nl.index.size())
    fail("pair stabilisation forces");
  for (const SphSnapshot* snap : {&m.sph.current, &m.sph.previous}) {
    const SphSnapshot& c = *snap;
    const std::size_t n = c.size();
    for (std::size_t k : {c.v.size(), c.h.size(), c.V.size(), c.volume_rate.size(), c.rho.size(),
                          c.c.size(), c.d.size(), c.B.size(), c.R.size(), c.tensile.size()})
      if (k != n) fail("SPH snapshot arrays of different lengths");
    if (n > np) fail("SPH snapshot of more particles than the model has");
  }
  // The residual-velocity tracking indexes bodies: each projectile and its plates.
  for (const CrossingsRecord& c : run.crossings) {
    if (c.projectile < 0 || c.projectile >= static_cast<int>(nb))
      fail("plate crossings' projectile");
    for (const PlateCrossing& p : c.plates)
      if (p.body < 0 || static_cast<std::size_t>(p.body) >= nb) fail("plate crossings' plate");
  }
}

}  // namespace

void writeCheckpoint(const std::string& path, const Model& model, const RunProgress& run) {
  const std::string tmp = temporaryFor(path);
  {
    h5::Handle file = h5::openFile(tmp, h5::Mode::Create);
    h5::writeAttribute(file, "format", std::string(kFormat));
    h5::writeAttribute(file, "format_version", kFormatVersion);
    writeRunMetadata(file);
    Writer w{h5::root(file)};
    transfer(w, const_cast<Model&>(model));  // the writer only reads
    transfer(w, const_cast<RunProgress&>(run));
  }
  renameInto(tmp, path);
}

Model readCheckpoint(const std::string& path, RunProgress& run) {
  const h5::Handle file = h5::openFile(path, h5::Mode::Read);
  if (!h5::hasAttribute(file, "format") || h5::readStringAttribute(file, "format") != kFormat)
    throw RunError(path + ": not a fesph checkpoint (an HDF5 file without its format mark)");
  const std::int64_t version = h5::readIntAttribute(file, "format_version");
  if (version < kOldestReadable || version > kFormatVersion)
    throw RunError(path + ": checkpoint format version " + std::to_string(version) +
                   ", this fesph reads versions " + std::to_string(kOldestReadable) + " to " +
                   std::to_string(kFormatVersion));
  Model model;
  try {
    Reader r{h5::root(file), path, version};
    transfer(r, model);
    transfer(r, run);
  } catch (const RunError& e) {
    const std::string what = e.what();
    throw RunError(what.rfind(path, 0) == 0 ? what : path + ": " + what);
  }
  checkConsistent(model, run, path, version >= 3);
  if (version < 3) restorePairStabilisation(model);
  return model;
}

std::string checkpointPath(const std::string& folder, long step) {
  char name[64];
  std::snprintf(name, sizeof name, "checkpoint_%09ld.h5", step);
  return (fs::path(folder) / name).string();
}

std::vector<std::string> listCheckpoints(const std::string& folder) {
  std::vector<std::string> found;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() == 23 && name.rfind("checkpoint_", 0) == 0 &&
        name.compare(20, 3, ".h5") == 0)
      found.push_back(entry.path().string());
  }
  std::sort(found.begin(), found.end());  // zero-padded steps: by name is by step
  return found;
}

void pruneCheckpoints(const std::string& folder, std::size_t keep) {
  std::vector<std::string> all = listCheckpoints(folder);
  for (std::size_t k = 0; k + keep < all.size(); ++k) {
    std::error_code ignored;
    fs::remove(all[k], ignored);
  }
}

}  // namespace fesph
