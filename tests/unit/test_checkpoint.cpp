// SPDX-License-Identifier: MIT
// Checkpoints and restarts: a run split by a checkpoint gives the same bits as one run (in the
// library and through `fesph run --restart`, with its series and histories continued), SIGINT
// leaves a checkpoint to continue from, a failing run keeps valid files, and bad checkpoint
// files give clear errors.
#include "core/common/error.hpp"
#include "core/io/checkpoint.hpp"
#include "core/io/hdf5.hpp"
#include "core/scene/scene.hpp"
#include "core/solver/step.hpp"
#include "tests/support/command.hpp"
#include "tests/support/temp_folder.hpp"
#include "tests/support/text.hpp"

#include <catch2/catch.hpp>
#include <toml++/toml.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <regex>
#include <sys/wait.h>
#include <thread>
#include <tuple>
#include <unistd.h>
#include <type_traits>
#include <vector>

using namespace fesph;
using fesph::testing::slurp;
namespace fs = std::filesystem;

namespace {

const std::string kScene = std::string(FESPH_TEST_DATA_DIR) + "/restart_impact.toml";
const std::string kLibrary = std::string(FESPH_SCENES_DIR) + "/materials.toml";

template <class T> bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool sameTies(const Particles& a, const Particles& b) {
  if (a.tie.size() != b.tie.size()) return false;
  for (std::size_t i = 0; i < a.tie.size(); ++i)
    if (a.tie[i].face != b.tie[i].face ||
        std::memcmp(a.tie[i].bary.data(), b.tie[i].bary.data(), 3 * sizeof(double)) != 0)
      return false;
  return true;
}

// Every state array step() reads and writes, bit for bit.
void requireSameState(const Model& a, const Model& b) {
  REQUIRE(a.step == b.step);
  REQUIRE(a.sph.controls.order_interval == b.sph.controls.order_interval);
  REQUIRE(a.symmetry.size() == b.symmetry.size());
  for (std::size_t k = 0; k < a.symmetry.size(); ++k) {
    REQUIRE(a.symmetry[k].axis == b.symmetry[k].axis);
    REQUIRE(sameBits(a.symmetry[k].position, b.symmetry[k].position));
  }
  REQUIRE(sameBits(a.time, b.time));
  REQUIRE(sameBits(a.dt, b.dt));
  REQUIRE(sameBits(a.nodes.x, b.nodes.x));
  REQUIRE(sameBits(a.nodes.v, b.nodes.v));
  REQUIRE(sameBits(a.nodes.f, b.nodes.f));
  REQUIRE(sameBits(a.nodes.m, b.nodes.m));
  REQUIRE(sameBits(a.elems.V, b.elems.V));
  REQUIRE(sameBits(a.elems.rho, b.elems.rho));
  REQUIRE(sameBits(a.elems.q, b.elems.q));
  REQUIRE(sameBits(a.elems.dt, b.elems.dt));
  REQUIRE(sameBits(a.elems.state, b.elems.state));
  REQUIRE(sameBits(a.elems.status, b.elems.status));
  REQUIRE(sameBits(a.particles.x, b.particles.x));
  REQUIRE(sameBits(a.particles.v, b.particles.v));
  REQUIRE(sameBits(a.particles.f, b.particles.f));
  REQUIRE(sameBits(a.particles.V, b.particles.V));
  REQUIRE(sameBits(a.particles.h, b.particles.h));
  REQUIRE(sameBits(a.particles.state, b.particles.state));
  REQUIRE(sameBits(a.particles.parent, b.particles.parent));
  REQUIRE(a.particles.id == b.particles.id);
  REQUIRE(sameTies(a.particles, b.particles));
  REQUIRE(sameBits(a.surfaces.exterior, b.surfaces.exterior));
  REQUIRE(sameBits(a.sph.neighbours.index, b.sph.neighbours.index));
  REQUIRE(a.conversion.converted == b.conversion.converted);
  REQUIRE(a.conversion.by_damage == b.conversion.by_damage);
  const EnergyBudget& ea = a.energy;
  const EnergyBudget& eb = b.energy;
  for (auto [x, y] : {std::pair{ea.kinetic, eb.kinetic}, {ea.internal, eb.internal},
                      {ea.contact, eb.contact}, {ea.conversion, eb.conversion},
                      {ea.plastic_work, eb.plastic_work}, {ea.initial, eb.initial}})
    REQUIRE(sameBits(x, y));
  REQUIRE(sameBits(ea.time, eb.time));
  REQUIRE(ea.step == eb.step);  // the history's rows are labelled with it
}

void stepTo(Model& model, long steps) {
  while (model.step < steps) step(model, model.controls.end_time);
}

int activeTies(const Model& m) {
  int n = 0;
  for (const Tie& t : m.particles.tie) n += t.active() ? 1 : 0;
  return n;
}


int shell(const std::string& cmd) {
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string runCmd(const std::string& args, const fs::path& log) {
  return std::string(FESPH_BINARY) + " run " + args + " --no-images --quiet > " + log.string() +
         " 2>&1";
}

std::size_t countOf(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
    ++n;
  return n;
}

std::string sceneRun(const fs::path& out, const std::string& extra = "") {
  return kScene + " --materials " + kLibrary + " --out " + out.string() +
         " --set simulation.end_time=1.5e-6 --set output.checkpoint_interval=0.5e-6"
         " --set output.checkpoints_kept=10 " + extra;
}

// The files of a run folder that must come out the same however the run was split.
void requireSameOutputs(const fs::path& a, const fs::path& b) {
  for (const char* f :
       {"history.csv", "elements.pvd", "particles.pvd", "residual_velocities.csv"})
    REQUIRE(slurp(a / f) == slurp(b / f));
  int series = 0;
  for (const auto& e : fs::directory_iterator(a)) {
    const std::string ext = e.path().extension().string();
    if (ext != ".vtu" && ext != ".vtp") continue;
    INFO(e.path().filename());
    REQUIRE(slurp(e.path()) == slurp(b / e.path().filename()));
    ++series;
  }
  REQUIRE(series == 6);
  const std::string dump = "h5dump -g /history ";
  REQUIRE(shell(dump + (a / "run.h5").string() + " > " + (a / "h5.txt").string()) == 0);
  REQUIRE(shell(dump + (b / "run.h5").string() + " > " + (b / "h5.txt").string()) == 0);
  std::string ha = slurp(a / "h5.txt"), hb = slurp(b / "h5.txt");
  ha = ha.substr(ha.find('\n'));  // the first line names the file
  hb = hb.substr(hb.find('\n'));
  REQUIRE(ha == hb);
}

/// The restart scene run 2N steps in one go (the reference) and N steps (to checkpoint), once
/// for the tests that continue from such a checkpoint. The scene converts elements to tied
/// particles in contact with the plate.
struct SplitRun {
  static constexpr long N = 90;
  Scene scene = loadScene(kScene, {}, kLibrary);
  Model unbroken = buildModel(scene);
  Model first = buildModel(scene);
  SplitRun() {
    stepTo(unbroken, 2 * N);
    stepTo(first, N);
  }
};

const SplitRun& splitRun() {
  static const SplitRun run;
  return run;
}

/// Formats before 11 hold no SPH volume rate (SphSnapshot::volume_rate): removes it from a
/// file written now, as such a file would lack it.
void dropVolumeRate(const h5::Handle& file) {
  for (const char* name : {"/sph/current/volume_rate", "/sph/previous/volume_rate"})
    REQUIRE(H5Ldelete(file.id(), name, H5P_DEFAULT) >= 0);
}

/// Formats 12 and older have no energy budget step: the reader takes the model's step less
/// one (the budget the last step closed), which requireSameState checks.
void dropEnergyStep(const h5::Handle& file) {
  REQUIRE(H5Adelete_by_name(file.id(), "/energy", "step", H5P_DEFAULT) >= 0);
}

/// Formats 13 and older keep the first projectile's plate crossings in /run/crossings itself
/// (its body, -1 for none, and its plates as groups "0", "1", ...), where format 14 keeps a
/// group per projectile. Lays the file's first projectile's out so, or none if it has none.
void crossingsOfFormat13(const h5::Handle& file) {
  REQUIRE(H5Lmove(file.id(), "/run/crossings", file.id(), "/run/crossings14", H5P_DEFAULT,
                  H5P_DEFAULT) >= 0);
  const h5::Handle old = h5::createGroup(h5::openGroup(file, "run"), "crossings");
  const h5::Handle now = h5::openGroup(file, "/run/crossings14");
  if (h5::readIntAttribute(now, "projectiles") == 0) {
    h5::writeAttribute(old, "projectile", std::int64_t{-1});
    h5::writeAttribute(old, "count", std::int64_t{0});
  } else {
    const h5::Handle first = h5::openGroup(now, "projectile_0");
    const std::int64_t plates = h5::readIntAttribute(first, "count");
    h5::writeAttribute(old, "projectile", h5::readIntAttribute(first, "projectile"));
    h5::writeAttribute(old, "count", plates);
    for (std::int64_t k = 0; k < plates; ++k)
      REQUIRE(H5Lmove(first.id(), std::to_string(k).c_str(), old.id(), std::to_string(k).c_str(),
                      H5P_DEFAULT, H5P_DEFAULT) >= 0);
  }
  REQUIRE(H5Ldelete(file.id(), "/run/crossings14", H5P_DEFAULT) >= 0);
}

/// Read from a file of format 10 or older, the volume rate is 0 (its first step weights the
/// forces with the particles' volumes of t^{n-1}, as the code that wrote it did). The one
/// `first` kept is put back, so that the rest of the file can be checked bit for bit.
void restoreVolumeRate(const Model& first, Model& continued) {
  const std::vector<double>& rate = continued.sph.current.volume_rate;
  REQUIRE(rate.size() == first.sph.current.volume_rate.size());
  REQUIRE(std::all_of(rate.begin(), rate.end(), [](double r) { return r == 0; }));
  continued.sph.current.volume_rate = first.sph.current.volume_rate;
}

/// The message of the RunError that reading the checkpoint `path` throws; empty when it reads.
std::string checkpointError(const std::string& path) {
  try {
    RunProgress p;
    readCheckpoint(path, p);
  } catch (const RunError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("a run continued from a checkpoint is bit-identical to an unbroken run",
          "[unit][checkpoint]") {
  // Reference: 2N steps in one go. Test: N steps, checkpoint, a fresh Model read from it,
  // N more.
  const SplitRun& run = splitRun();
  const Model& first = run.first;
  REQUIRE(first.conversion.converted > 0);  // the checkpoint holds particles ...
  REQUIRE(activeTies(first) > 0);           // ... tied to element faces
  testing::TempFolder dir("checkpoint_bits");
  const std::string path = checkpointPath(dir.path.string(), first.step);
  RunProgress progress;
  progress.scene_text = run.scene.source;
  writeCheckpoint(path, first, progress);
  REQUIRE(!fs::exists(path + ".tmp"));

  RunProgress read;
  Model continued = readCheckpoint(path, read);
  REQUIRE(read.scene_text == run.scene.source);
  REQUIRE(continued.symmetry.size() == 1);  // a half model: its plane is in the checkpoint
  requireSameState(first, continued);
  stepTo(continued, 2 * run.N);
  requireSameState(run.unbroken, continued);
}

namespace {

// Arrays of numbers and of packed structs of numbers (checkpoint.cpp's Layout): byte for byte.
template <class T> bool same(const std::vector<T>& a, const std::vector<T>& b) {
  return sameBits(a, b);
}
bool same(const std::vector<std::vector<int>>& a, const std::vector<std::vector<int>>& b) {
  return a == b;
}
bool same(double a, double b) { return sameBits(a, b); }
bool same(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), 24) == 0; }
bool same(const std::string& a, const std::string& b) { return a == b; }
template <class T> std::enable_if_t<std::is_integral_v<T> || std::is_enum_v<T>, bool>
same(T a, T b) {
  return a == b;
}

// A value for every scalar the checkpoint stores, each unlike its default and the others.
void setSentinels(Model& m, RunProgress& r) {
  SolverControls& c = m.controls;
  c.contact.passes = 7;
  c.contact.friction = 0.11;
  c.contact.depth_tolerance = 0.12;
  c.conversion.mode = ConversionMode::Erosion;
  c.conversion.plastic_strain = 0.13;
  c.conversion.min_volume_ratio = 0.14;
  c.conversion.max_volume_ratio = 15.0;
  c.conversion.min_dt_ratio = 0.16;
  c.end_time = 1.7e-3;
  c.courant = 0.18;
  c.bulk_linear = 0.19;
  c.bulk_quadratic = 1.21;
  c.average_nodal_pressure = !c.average_nodal_pressure;
  c.anp_element_fraction = 0.22;
  c.dt_growth = 1.23;
  c.dt_min = 2.4e-12;
  SphControls& s = m.sph.controls;
  s.kappa = 1.25;
  s.av_alpha = 0.26;
  s.av_beta = 0.27;
  s.artificial_stress = !s.artificial_stress;
  s.as_epsilon = 0.28;
  s.max_condition = 290.0;
  s.min_neighbours = 9;
  s.as_exponent = 3;
  s.contact_passes = 5;
  s.dt_factor = 0.31;
  s.verlet_skin = 0.32;
  s.order_interval = 33;
  m.walls.push_back({Vec3(1e-3, 2e-3, 3e-3), Vec3(0.6, 0.0, 0.8), 0.34});
  EnergyBudget& e = m.energy;
  double x = 1.01;
  for (double* term : {&e.kinetic, &e.internal, &e.bulk_viscosity, &e.artificial_viscosity,
                       &e.plastic_work, &e.contact, &e.contact_through_half, &e.eroded,
                       &e.conversion, &e.initial, &e.kinetic_half, &e.time})
    *term = (x += 0.01);
  e.momentum = Vec3(0.35, -0.36, 0.37);
  e.step = 50;  // not the model's step less one, which a reader of format 12 would take
  m.conversion.eroded = 38;
  m.conversion.by_safety = 39;
  m.conversion.eroded_mass = 4.1e-3;
  m.dt_limiter = "particle 43";

  r.scene_text = "title = \"sentinel\"\n";
  r.overrides = {"simulation.end_time=1e-6", "bodies.0.velocity=[0, 0, -44]"};
  r.scene_path = "/a/scene.toml";
  r.material_library = "/a/materials.toml";
  r.series_outputs = 45;
  r.output_index = 46;
  r.next_output = 4.7e-6;
  r.next_checkpoint = 4.8e-6;
  r.history_rows = 49;
  PlateCrossing p;
  p.body = 1;
  p.name = "plate_50";
  p.normal = Vec3(0.0, 0.6, 0.8);
  p.front = Vec3(0.51, 0.52, 0.53);
  p.thickness = 5.4e-3;
  p.measure_depth = 5.5e-3;
  p.t_contact = 5.6e-6;
  p.t_measured = 5.7e-6;
  p.velocity = Vec3(58, 59, 60);
  p.speed = 61;
  p.mass_fraction = 0.62;
  p.through_velocity = Vec3(63, 64, 65);
  p.through_mass_fraction = 0.66;
  PlateCrossing q = p;  // a second projectile's: the plate met again, later, slower
  q.t_contact = 6.7e-6;
  q.t_measured = 6.8e-6;
  q.speed = 69;
  r.crossings = {{0, {p}}, {1, {q, p}}};
}

}  // namespace

TEST_CASE("every quantity a checkpoint stores reads back bit for bit", "[unit][checkpoint]") {
  // The bit-identical restart above shows the state that steers the next steps is complete;
  // this one shows each stored quantity comes back as written, also those a continued run
  // only reports (counters, energy terms, the run's progress) or that a short continuation
  // need not touch (controls, walls). Each scalar is set to a value unlike its default.
  const SplitRun& run = splitRun();
  Model a = run.first;
  RunProgress ra;
  setSentinels(a, ra);
  testing::TempFolder dir("checkpoint_fields");
  const std::string path = checkpointPath(dir.path.string(), a.step);
  writeCheckpoint(path, a, ra);
  RunProgress rb;
  const Model b = readCheckpoint(path, rb);
  REQUIRE(a.particles.size() > 0);
  REQUIRE(activeTies(a) > 0);

  const Nodes &na = a.nodes, &nb = b.nodes;
  CHECK(same(na.x, nb.x));
  CHECK(same(na.x0, nb.x0));
  CHECK(same(na.v, nb.v));
  CHECK(same(na.f, nb.f));
  CHECK(same(na.m, nb.m));
  CHECK(same(na.body, nb.body));
  CHECK(same(na.fix, nb.fix));
  const Elements &ea = a.elems, &eb = b.elems;
  CHECK(same(ea.conn, eb.conn));
  CHECK(same(ea.body, eb.body));
  CHECK(same(ea.material, eb.material));
  CHECK(same(ea.V0, eb.V0));
  CHECK(same(ea.V, eb.V));
  CHECK(same(ea.dV, eb.dV));
  CHECK(same(ea.rho, eb.rho));
  CHECK(same(ea.q, eb.q));
  CHECK(same(ea.div_v, eb.div_v));
  CHECK(same(ea.dt, eb.dt));
  CHECK(same(ea.len, eb.len));
  CHECK(same(ea.len0, eb.len0));
  CHECK(same(ea.state, eb.state));
  CHECK(same(ea.status, eb.status));
  const Particles &pa = a.particles, &pb = b.particles;
  CHECK(same(pa.x, pb.x));
  CHECK(same(pa.v, pb.v));
  CHECK(same(pa.f, pb.f));
  CHECK(same(pa.m, pb.m));
  CHECK(same(pa.V, pb.V));
  CHECK(same(pa.rho, pb.rho));
  CHECK(same(pa.h, pb.h));
  CHECK(same(pa.d0, pb.d0));
  CHECK(same(pa.dt, pb.dt));
  CHECK(same(pa.state, pb.state));
  CHECK(same(pa.body, pb.body));
  CHECK(same(pa.material, pb.material));
  CHECK(same(pa.parent, pb.parent));
  CHECK(same(pa.id, pb.id));
  CHECK(sameTies(pa, pb));

  REQUIRE(a.materials.size() == b.materials.size());
  for (std::size_t k = 0; k < a.materials.size(); ++k) {
    const Material &x = a.materials[k], &y = b.materials[k];
    INFO("material " << x.name);
    CHECK(same(x.name, y.name));
    CHECK(same(x.source, y.source));
    CHECK(same(x.status, y.status));
    CHECK(same(x.strength, y.strength));
    CHECK(same(x.damage, y.damage));
    CHECK(same(x.eos, y.eos));
    for (auto [u, v] : {std::pair{x.rho0, y.rho0}, {x.E, y.E}, {x.nu, y.nu}, {x.G, y.G},
                        {x.K, y.K}, {x.cp, y.cp}, {x.T_room, y.T_room}, {x.T_melt, y.T_melt},
                        {x.taylor_quinney, y.taylor_quinney}, {x.A, y.A}, {x.B, y.B},
                        {x.n, y.n}, {x.C, y.C}, {x.m, y.m}, {x.eps_dot0, y.eps_dot0},
                        {x.D1, y.D1}, {x.D2, y.D2}, {x.D3, y.D3}, {x.D4, y.D4}, {x.D5, y.D5},
                        {x.c0, y.c0}, {x.s, y.s}, {x.gamma0, y.gamma0},
                        {x.erosion_strain, y.erosion_strain}})
      CHECK(same(u, v));
  }
  REQUIRE(a.bodies.size() == b.bodies.size());
  for (std::size_t k = 0; k < a.bodies.size(); ++k) {
    const Body &x = a.bodies[k], &y = b.bodies[k];
    CHECK(same(x.name, y.name));
    CHECK(same(x.material, y.material));
    CHECK(same(x.discretisation, y.discretisation));
    CHECK(same(x.is_projectile, y.is_projectile));
    CHECK(same(x.node_begin, y.node_begin));
    CHECK(same(x.node_end, y.node_end));
    CHECK(same(x.elem_begin, y.elem_begin));
    CHECK(same(x.elem_end, y.elem_end));
  }
  REQUIRE(b.walls.size() == 1);
  CHECK(same(a.walls[0].point, b.walls[0].point));
  CHECK(same(a.walls[0].normal, b.walls[0].normal));
  CHECK(same(a.walls[0].friction, b.walls[0].friction));
  REQUIRE(b.symmetry.size() == a.symmetry.size());
  CHECK(same(a.symmetry[0].axis, b.symmetry[0].axis));
  CHECK(same(a.symmetry[0].position, b.symmetry[0].position));

  const Surfaces &sa = a.surfaces, &sb = b.surfaces;
  CHECK(same(sa.table, sb.table));
  CHECK(same(sa.elem_faces, sb.elem_faces));
  CHECK(same(sa.exterior, sb.exterior));
  CHECK(same(sa.slave_nodes, sb.slave_nodes));
  CHECK(same(sa.node_face_count, sb.node_face_count));
  CHECK(same(sa.node_slot, sb.node_slot));

  const SphWorkspace &wa = a.sph, &wb = b.sph;
  CHECK(same(wa.neighbours.offset, wb.neighbours.offset));
  CHECK(same(wa.neighbours.index, wb.neighbours.index));
  CHECK(same(wa.pair_grad, wb.pair_grad));
  CHECK(same(wa.pair_stab, wb.pair_stab));
  for (auto [x, y] : {std::pair{&wa.current, &wb.current}, {&wa.previous, &wb.previous}}) {
    CHECK(same(x->x, y->x));
    CHECK(same(x->v, y->v));
    CHECK(same(x->h, y->h));
    CHECK(same(x->V, y->V));
    CHECK(same(x->volume_rate, y->volume_rate));
    CHECK(same(x->rho, y->rho));
    CHECK(same(x->c, y->c));
    CHECK(same(x->d, y->d));
    CHECK(same(x->B, y->B));
    CHECK(same(x->R, y->R));
    CHECK(same(x->tensile, y->tensile));
  }
  CHECK(same(wa.corrected, wb.corrected));
  CHECK(same(wa.velocity_grad, wb.velocity_grad));
  CHECK(same(wa.velocity_grad_prev, wb.velocity_grad_prev));
  CHECK(same(wa.stress_b, wb.stress_b));
  CHECK(same(wa.plastic_work, wb.plastic_work));
  CHECK(same(wa.av_work, wb.av_work));
  CHECK(same(wa.contact_radius, wb.contact_radius));
  CHECK(same(wa.contact_spacing, wb.contact_spacing));
  CHECK(same(wa.contact_pairs, wb.contact_pairs));

  const SolverControls &ca = a.controls, &cb = b.controls;
  CHECK(same(ca.contact.passes, cb.contact.passes));
  CHECK(same(ca.contact.friction, cb.contact.friction));
  CHECK(same(ca.contact.depth_tolerance, cb.contact.depth_tolerance));
  CHECK(same(ca.conversion.mode, cb.conversion.mode));
  for (auto [u, v] :
       {std::pair{ca.conversion.plastic_strain, cb.conversion.plastic_strain},
        {ca.conversion.min_volume_ratio, cb.conversion.min_volume_ratio},
        {ca.conversion.max_volume_ratio, cb.conversion.max_volume_ratio},
        {ca.conversion.min_dt_ratio, cb.conversion.min_dt_ratio}, {ca.end_time, cb.end_time},
        {ca.courant, cb.courant}, {ca.bulk_linear, cb.bulk_linear},
        {ca.bulk_quadratic, cb.bulk_quadratic}, {ca.anp_element_fraction, cb.anp_element_fraction},
        {ca.dt_growth, cb.dt_growth}, {ca.dt_min, cb.dt_min}})
    CHECK(same(u, v));
  CHECK(same(ca.average_nodal_pressure, cb.average_nodal_pressure));
  const SphControls &xa = wa.controls, &xb = wb.controls;
  for (auto [u, v] : {std::pair{xa.kappa, xb.kappa}, {xa.av_alpha, xb.av_alpha},
                      {xa.av_beta, xb.av_beta}, {xa.as_epsilon, xb.as_epsilon},
                      {xa.max_condition, xb.max_condition}, {xa.dt_factor, xb.dt_factor},
                      {xa.verlet_skin, xb.verlet_skin}})
    CHECK(same(u, v));
  CHECK(same(xa.artificial_stress, xb.artificial_stress));
  CHECK(same(xa.min_neighbours, xb.min_neighbours));
  CHECK(same(xa.as_exponent, xb.as_exponent));
  CHECK(same(xa.contact_passes, xb.contact_passes));
  CHECK(same(xa.order_interval, xb.order_interval));

  const EnergyBudget &ga = a.energy, &gb = b.energy;
  for (auto [u, v] :
       {std::pair{ga.kinetic, gb.kinetic}, {ga.internal, gb.internal},
        {ga.bulk_viscosity, gb.bulk_viscosity}, {ga.artificial_viscosity, gb.artificial_viscosity},
        {ga.plastic_work, gb.plastic_work}, {ga.contact, gb.contact},
        {ga.contact_through_half, gb.contact_through_half}, {ga.eroded, gb.eroded},
        {ga.conversion, gb.conversion}, {ga.initial, gb.initial},
        {ga.kinetic_half, gb.kinetic_half}, {ga.time, gb.time}})
    CHECK(same(u, v));
  CHECK(same(ga.momentum, gb.momentum));
  CHECK(same(ga.step, gb.step));
  CHECK(same(a.conversion.eroded, b.conversion.eroded));
  CHECK(same(a.conversion.converted, b.conversion.converted));
  CHECK(same(a.conversion.by_damage, b.conversion.by_damage));
  CHECK(same(a.conversion.by_safety, b.conversion.by_safety));
  CHECK(same(a.conversion.eroded_mass, b.conversion.eroded_mass));
  CHECK(same(a.node_corner_offset, b.node_corner_offset));
  CHECK(same(a.node_corners, b.node_corners));
  CHECK(same(a.corner_force, b.corner_force));
  CHECK(same(a.time, b.time));
  CHECK(same(a.dt, b.dt));
  CHECK(same(a.step, b.step));
  CHECK(same(a.dt_limiter, b.dt_limiter));

  CHECK(same(ra.scene_text, rb.scene_text));
  CHECK(ra.overrides == rb.overrides);
  CHECK(same(ra.scene_path, rb.scene_path));
  CHECK(same(ra.material_library, rb.material_library));
  CHECK(same(ra.series_outputs, rb.series_outputs));
  CHECK(same(ra.output_index, rb.output_index));
  CHECK(same(ra.next_output, rb.next_output));
  CHECK(same(ra.next_checkpoint, rb.next_checkpoint));
  CHECK(same(ra.history_rows, rb.history_rows));
  REQUIRE(rb.crossings.size() == ra.crossings.size());
  for (std::size_t s = 0; s < ra.crossings.size(); ++s) {
    CHECK(same(ra.crossings[s].projectile, rb.crossings[s].projectile));
    REQUIRE(rb.crossings[s].plates.size() == ra.crossings[s].plates.size());
  }
  CHECK(same(rb.crossings[1].plates[0].speed, 69.0));  // each projectile's own table
  const PlateCrossing &x = ra.crossings[0].plates[0], &y = rb.crossings[0].plates[0];
  CHECK(same(x.body, y.body));
  CHECK(same(x.name, y.name));
  CHECK(same(x.normal, y.normal));
  CHECK(same(x.front, y.front));
  CHECK(same(x.velocity, y.velocity));
  CHECK(same(x.through_velocity, y.through_velocity));
  for (auto [u, v] : {std::pair{x.thickness, y.thickness}, {x.measure_depth, y.measure_depth},
                      {x.t_contact, y.t_contact}, {x.t_measured, y.t_measured},
                      {x.speed, y.speed}, {x.mass_fraction, y.mass_fraction},
                      {x.through_mass_fraction, y.through_mass_fraction}})
    CHECK(same(u, v));
}

TEST_CASE("a checkpoint of format 13 gives back its one projectile's plate crossings",
          "[unit][checkpoint]") {
  // Format 14 keeps every projectile's table; older files hold the scene's first one's, in
  // another layout, and a restart from them tracks that one only.
  const SplitRun& run = splitRun();
  Model a = run.first;
  RunProgress ra;
  setSentinels(a, ra);
  REQUIRE(ra.crossings.size() == 2);
  testing::TempFolder dir("checkpoint_format13");
  const std::string path = checkpointPath(dir.path.string(), a.step);
  for (const bool none : {false, true}) {
    if (none) ra.crossings.clear();
    writeCheckpoint(path, a, ra);
    {
      const h5::Handle f = h5::openFile(path, h5::Mode::ReadWrite);
      crossingsOfFormat13(f);
      h5::writeAttribute(f, "format_version", std::int64_t{13});
    }
    RunProgress rb;
    readCheckpoint(path, rb);
    if (none) {
      CHECK(rb.crossings.empty());  // a scene without a projectile: nothing tracked
      continue;
    }
    REQUIRE(rb.crossings.size() == 1);
    CHECK(rb.crossings[0].projectile == 0);
    REQUIRE(rb.crossings[0].plates.size() == 1);
    CHECK(rb.crossings[0].plates[0].name == "plate_50");
    CHECK(rb.crossings[0].plates[0].speed == 61);
  }
}

TEST_CASE("a checkpoint whose parts do not fit together is refused naming the part",
          "[unit][checkpoint]") {
  // A damaged or hand-edited file must stop the restart with a message, not let step() index
  // out of its arrays. Each case breaks one rule of the reader's consistency check, by one
  // (an index equal to the count, a length one short or one long).
  const Model& good = splitRun().first;
  REQUIRE(good.particles.size() > 0);
  REQUIRE(good.sph.neighbours.pairs() > 0);
  const int nn = static_cast<int>(good.nodes.size());
  const int tied = [&] {
    for (std::size_t i = 0; i < good.particles.size(); ++i)
      if (good.particles.tie[i].active()) return static_cast<int>(i);
    return -1;
  }();
  REQUIRE(tied >= 0);
  struct Case {
    const char* what;  ///< the part the message must name
    std::function<void(Model&)> damage;
  };
  const std::vector<Case> cases = {
      {"node arrays of different lengths", [](Model& m) { m.nodes.x0.pop_back(); }},
      {"element status", [](Model& m) { m.elems.status[0] = static_cast<ElemStatus>(3); }},
      {"element connectivity", [=](Model& m) { m.elems.conn[0][2] = nn; }},
      {"particle tie", [=](Model& m) { m.particles.tie[tied].face[1] = nn; }},
      {"particle tie", [=](Model& m) { m.particles.tie[tied].face[2] = -1; }},
      {"neighbour list", [](Model& m) {
         m.sph.neighbours.index[0] = static_cast<int>(m.particles.size());
       }},
      {"SPH snapshot of more particles than the model has", [](Model& m) {
         m.sph.current.resize(m.particles.size() + 1);
       }},
      {"node corner lists", [](Model& m) { m.node_corners.pop_back(); }},
      {"body ranges", [](Model& m) { m.bodies[0].elem_end = m.elems.size() + 1; }},
  };
  testing::TempFolder dir("inconsistent_checkpoints");
  const std::string path = (dir.path / "damaged.h5").string();
  for (const Case& c : cases) {
    INFO(c.what);
    Model m = good;
    c.damage(m);
    writeCheckpoint(path, m, RunProgress{});
    const std::string error = checkpointError(path);
    INFO(error);
    CHECK(error.find(path + ": inconsistent checkpoint: " + c.what) != std::string::npos);
  }
  // The residual-velocity tracking's body indices: each projectile's and each of its plates'
  // (broken in the second projectile's tracking: every one is checked, not the first only).
  const int nb = static_cast<int>(good.bodies.size());
  for (const auto& [projectile, plate, what] :
       {std::tuple{nb, 0, "plate crossings' projectile"}, std::tuple{-1, 0, "plate crossings' projectile"},
        std::tuple{0, nb, "plate crossings' plate"}, std::tuple{0, -1, "plate crossings' plate"}}) {
    RunProgress run;
    run.crossings.resize(2);
    run.crossings[0] = {0, {PlateCrossing{}}};
    run.crossings[0].plates[0].body = 0;
    run.crossings[1] = {projectile, {PlateCrossing{}}};
    run.crossings[1].plates[0].body = plate;
    writeCheckpoint(path, good, run);
    const std::string error = checkpointError(path);
    INFO(error);
    CHECK(error.find(path + ": inconsistent checkpoint: " + what) != std::string::npos);
    run.crossings[1].projectile = nb - 1;
    run.crossings[1].plates[0].body = nb - 1;
    writeCheckpoint(path, good, run);
    CHECK(checkpointError(path).empty());
  }
  // What the file itself lays out: a list of groups longer than any model holds, and rows
  // whose offsets run backwards.
  writeCheckpoint(path, good, RunProgress{});
  for (const auto& [edit, what] :
       {std::pair<std::function<void(const h5::Handle&)>, std::string>{
            [](const h5::Handle& f) {
              h5::writeAttribute(h5::openGroup(f, "materials"), "count", std::int64_t{2000000});
            },
            "bad count count"},
        {[](const h5::Handle& f) {
           const h5::Handle s = h5::openGroup(f, "surfaces");
           const auto [rows, cols] = h5::arrayShape(s, "slave_nodes_offset");
           REQUIRE(rows >= 3);
           std::vector<std::size_t> offset(rows);
           h5::readArray(s, "slave_nodes_offset", h5::nativeType<std::size_t>(), offset.data());
           offset[1] = offset[2] + 1;  // row 0 ends after row 1 does
           REQUIRE(H5Ldelete(s.id(), "slave_nodes_offset", H5P_DEFAULT) >= 0);
           h5::writeArray(s, "slave_nodes_offset", h5::nativeType<std::size_t>(), offset.data(),
                          rows, cols);
         },
         "bad row offsets of slave_nodes"}}) {
    INFO(what);
    const std::string copy = (dir.path / "edited.h5").string();
    fs::copy_file(path, copy, fs::copy_options::overwrite_existing);
    {
      const h5::Handle f = h5::openFile(copy, h5::Mode::ReadWrite);
      edit(f);
    }
    const std::string error = checkpointError(copy);
    INFO(error);
    CHECK(error.find(what) != std::string::npos);
  }
}

TEST_CASE("pruning keeps the newest checkpoints by step and no other file", "[unit][checkpoint]") {
  // output.checkpoints_kept (README): the newest N checkpoints stay in the run folder. Names
  // carry the step zero-padded to 9 digits, so name order is step order; files that only look
  // like checkpoints (a temporary being written, another width) are not theirs to delete.
  testing::TempFolder dir("prune_checkpoints");
  const std::string folder = dir.path.string();
  for (long step : {100, 5, 20}) std::ofstream(checkpointPath(folder, step)) << step;
  const std::vector<std::string> others = {"checkpoint_000000003.h5.tmp", "checkpoint_12.h5",
                                           "checkpoint_0000000001.h5", "history.csv"};
  for (const std::string& name : others) std::ofstream(dir.path / name) << name;
  CHECK(fs::path(checkpointPath(folder, 5)).filename() == "checkpoint_000000005.h5");
  CHECK(listCheckpoints(folder) == std::vector<std::string>{checkpointPath(folder, 5),
                                                            checkpointPath(folder, 20),
                                                            checkpointPath(folder, 100)});
  pruneCheckpoints(folder, 3);
  CHECK(listCheckpoints(folder).size() == 3);
  pruneCheckpoints(folder, 2);
  CHECK(listCheckpoints(folder) ==
        std::vector<std::string>{checkpointPath(folder, 20), checkpointPath(folder, 100)});
  pruneCheckpoints(folder, 1);
  CHECK(listCheckpoints(folder) == std::vector<std::string>{checkpointPath(folder, 100)});
  for (const std::string& name : others) CHECK(fs::exists(dir.path / name));
}

TEST_CASE("a checkpoint of format 2 (no pair stabilisation forces) continues bit-identically",
          "[unit][checkpoint]") {
  // Format 2 did not store the last step's pair stabilisation forces; the reader recomputes
  // them from the stored snapshot, so the continued run is the unbroken run, bit for bit.
  const SplitRun& run = splitRun();
  const Model& first = run.first;
  REQUIRE(first.sph.neighbours.pairs() > 0);
  // the forces to restore are not all zero (approaching pairs feel the viscosity)
  REQUIRE(std::any_of(first.sph.pair_stab.begin(), first.sph.pair_stab.end(),
                      [](const Vec3& f) { return f.squaredNorm() > 0; }));
  testing::TempFolder dir("checkpoint_format2");
  const std::string path = checkpointPath(dir.path.string(), first.step);
  writeCheckpoint(path, first, RunProgress{});
  {
    const h5::Handle f = h5::openFile(path, h5::Mode::ReadWrite);
    REQUIRE(H5Ldelete(f.id(), "/sph/pair_stab", H5P_DEFAULT) >= 0);
    dropVolumeRate(f);
    dropEnergyStep(f);
    crossingsOfFormat13(f);
    h5::writeAttribute(f, "format_version", std::int64_t{2});
  }
  RunProgress read;
  Model continued = readCheckpoint(path, read);
  REQUIRE(continued.symmetry.empty());  // not in format 2 (nor 3, 4): a restart takes the scene's
  continued.symmetry = first.symmetry;
  // nor the particles' ids (formats 2-5 were never renumbered: the reader takes the index);
  // this file comes from a renumbered run
  REQUIRE(continued.particles.id.size() == first.particles.id.size());
  continued.particles.id = first.particles.id;
  restoreVolumeRate(first, continued);
  REQUIRE(sameBits(continued.sph.pair_stab, first.sph.pair_stab));
  requireSameState(first, continued);
  stepTo(continued, 2 * run.N);
  requireSameState(run.unbroken, continued);
}

TEST_CASE("checkpoints of formats 6 to 8 (with scratch arrays) continue bit-identically",
          "[unit][checkpoint]") {
  // Format 6 also stored the pair gradients in the previous configuration, formats 2-7 the
  // last step's neighbour list and pair gradients, formats 2-8 the nodal volumes of the
  // average nodal pressure, and formats 2-9 the velocities before the step's corrections:
  // scratch, which formats 7, 8, 9 and 10 dropped. The reader must accept such files and
  // skip those arrays. Here the gradients and volumes are NaN and the list's indices out of
  // range: a reader that checked them would refuse the file, one that used them in place of
  // the current ones would not reproduce the unbroken run.
  const SplitRun& run = splitRun();
  const Model& first = run.first;
  const std::size_t pairs = first.sph.neighbours.pairs();
  REQUIRE(pairs > 0);
  for (const std::int64_t version : {6, 7, 8}) {
    INFO("format " << version);
    testing::TempFolder dir("checkpoint_format" + std::to_string(version));
    const std::string path = checkpointPath(dir.path.string(), first.step);
    writeCheckpoint(path, first, RunProgress{});
    {
      const h5::Handle f = h5::openFile(path, h5::Mode::ReadWrite);
      const h5::Handle sph = h5::openGroup(f, "sph");
      const std::vector<double> nan(3 * pairs, std::numeric_limits<double>::quiet_NaN());
      const std::vector<int> wild(pairs, -7);
      const std::vector<std::uint64_t> offsets(first.particles.size() + 1, pairs + 11);
      for (const char* name : {"pair_grad_prev", "pair_grad_last", "neighbour_last_index",
                               "neighbour_last_offset"})
        REQUIRE(!h5::exists(sph, name));
      if (version == 6)
        h5::writeArray(sph, "pair_grad_prev", H5T_NATIVE_DOUBLE, nan.data(), pairs, 3);
      if (version <= 7) {
        h5::writeArray(sph, "pair_grad_last", H5T_NATIVE_DOUBLE, nan.data(), pairs, 3);
        h5::writeArray(sph, "neighbour_last_index", H5T_NATIVE_INT, wild.data(), pairs, 1);
        h5::writeArray(sph, "neighbour_last_offset", H5T_NATIVE_UINT64, offsets.data(),
                       offsets.size(), 1);
      }
      const h5::Handle scratch = h5::openGroup(f, "scratch");
      const std::vector<double> nan_nodes(first.nodes.size(),
                                          std::numeric_limits<double>::quiet_NaN());
      for (const char* name : {"nodal_volume", "nodal_volume0"}) {
        REQUIRE(!h5::exists(scratch, name));
        h5::writeArray(scratch, name, H5T_NATIVE_DOUBLE, nan_nodes.data(), nan_nodes.size(), 1);
      }
      // formats 2-9 also held the velocities before the corrections: here one NaN vector each,
      // which a reader that checked their length would refuse
      for (const char* name : {"v_node_free", "v_particle_free"}) {
        REQUIRE(!h5::exists(scratch, name));
        h5::writeArray(scratch, name, H5T_NATIVE_DOUBLE, nan_nodes.data(), 1, 3);
      }
      dropVolumeRate(f);
      dropEnergyStep(f);
      crossingsOfFormat13(f);
      h5::writeAttribute(f, "format_version", version);
    }
    RunProgress read;
    Model continued = readCheckpoint(path, read);
    restoreVolumeRate(first, continued);
    requireSameState(first, continued);
    stepTo(continued, 2 * run.N);
    requireSameState(run.unbroken, continued);
  }
}

TEST_CASE("fesph run --restart continues the series and histories, also after a SIGINT",
          "[unit][checkpoint]") {
  testing::TempFolder dir("restart_cli");
  const fs::path whole = dir.path / "whole", split = dir.path / "split", cut = dir.path / "cut";
  REQUIRE(shell(runCmd(sceneRun(whole), dir.path / "whole.log")) == 0);
  const std::vector<std::string> ckpts = listCheckpoints(whole.string());
  REQUIRE(ckpts.size() == 3);  // at 0.5 and 1.0 us and at the end
  {
    // The figures of merit count the neighbour-list builds: the Verlet skin must save most.
    const std::string log = slurp(dir.path / "whole.log");
    INFO(log);
    std::smatch m;
    REQUIRE(std::regex_search(log, m, std::regex("neighbour lists  ([0-9]+) SPH, ([0-9]+) contact "
                                                 "and ([0-9]+) mirror builds in ([0-9]+) steps, "
                                                 "([0-9]+) particles re-seated")));
    CHECK(std::stol(m[1]) >= 1);
    CHECK(std::stol(m[1]) < std::stol(m[4]) / 2);
    CHECK(std::stol(m[2]) < std::stol(m[4]) / 2);
    // the half model's image: two lists (SPH and contact), built afresh less than every step
    // although particles are born near the plane in most steps
    CHECK(std::stol(m[3]) >= 1);
    CHECK(std::stol(m[3]) < 2 * std::stol(m[4]));
  }

  // Split run: everything the whole run wrote (as if it had been stopped late), but only
  // its first checkpoint; the restart must cut the outputs back to it and go on.
  fs::copy(whole, split);
  for (const std::string& c : listCheckpoints(split.string())) fs::remove(c);
  const fs::path from = split / fs::path(ckpts[0]).filename();
  fs::copy_file(ckpts[0], from);
  REQUIRE(shell(runCmd("--restart " + from.string(), dir.path / "split.log")) == 0);
  requireSameOutputs(whole, split);
  REQUIRE(listCheckpoints(split.string()).size() == 3);

  // Into another folder (twice: the second finds the first one's files): fresh series and
  // histories there, from the checkpoint on, ending in the same state.
  const fs::path other = dir.path / "other";
  for (int k = 0; k < 2; ++k)
    REQUIRE(shell(runCmd("--restart " + ckpts[1] + " --out " + other.string(),
                         dir.path / "other.log")) == 0);
  const auto lastLine = [](const std::string& text) {
    return text.substr(text.rfind('\n', text.size() - 2) + 1);
  };
  REQUIRE(lastLine(slurp(other / "history.csv")) == lastLine(slurp(whole / "history.csv")));
  REQUIRE(slurp(other / "history.csv").size() < slurp(whole / "history.csv").size());

  // Interrupted run: SIGINT once it has written a few history rows (5 steps a row).
  const pid_t pid = testing::startAndWait(runCmd(sceneRun(cut), dir.path / "cut.log"), [&] {
    return countOf(slurp(cut / "history.csv"), "\n") >= 8;
  });
  REQUIRE(pid > 0);
  const int code = testing::signalAndWait(pid, SIGINT);
  const std::string log = slurp(dir.path / "cut.log");
  INFO(log);
  REQUIRE(code == 1);
  REQUIRE(log.find("interrupted (Interrupt)") != std::string::npos);
  const std::vector<std::string> cut_ckpts = listCheckpoints(cut.string());
  REQUIRE(!cut_ckpts.empty());
  RunProgress progress;
  const Model stopped = readCheckpoint(cut_ckpts.back(), progress);
  REQUIRE(stopped.step > 0);
  REQUIRE(stopped.time < 1.5e-6);
  REQUIRE(log.find("checkpoint written to " + cut_ckpts.back()) != std::string::npos);
  // Plate contact (at ~0.14 us) comes before the first output after t = 0 (1 us): a stop in
  // between must still leave the contact time in the table, not the table of t = 0.
  const auto contactTime = [&](const fs::path& csv) {
    const std::string text = slurp(csv);
    const std::size_t row = text.find("\n1,plate,");
    REQUIRE(row != std::string::npos);
    const std::size_t at = row + 9;
    return text.substr(at, text.find(',', at) - at);
  };
  const std::string t_contact = contactTime(whole / "residual_velocities.csv");
  REQUIRE(!t_contact.empty());
  INFO("stopped at " << stopped.time << " s, contact at " << t_contact << " s");
  REQUIRE(stopped.time > std::stod(t_contact));
  REQUIRE(contactTime(cut / "residual_velocities.csv") == t_contact);
  REQUIRE(shell(runCmd("--restart " + cut_ckpts.back(), dir.path / "rest.log")) == 0);
  requireSameOutputs(whole, cut);
}

TEST_CASE("a run killed outright leaves a summary that says how far it got", "[unit][checkpoint]") {
  // SIGKILL cannot be caught, so the end-of-run summary is never written; the one rewritten
  // at every field output must then say "running" at the last output the series lists (or,
  // killed between that output's files and its summary, the one before).
  testing::TempFolder dir("killed");
  const fs::path out = dir.path / "run";
  const pid_t pid = testing::startAndWait(
      runCmd(sceneRun(out, "--set output.interval=0.25e-6"), dir.path / "log"),
      [&] { return countOf(slurp(out / "elements.pvd"), "<DataSet") >= 3; });
  REQUIRE(pid > 0);
  REQUIRE(testing::signalAndWait(pid, SIGKILL) == -1);  // ended by the signal
  const std::string pvd = slurp(out / "elements.pvd");
  std::vector<double> times;
  for (std::size_t at = pvd.find("timestep=\""); at != std::string::npos;
       at = pvd.find("timestep=\"", at + 1))
    times.push_back(std::stod(pvd.substr(at + 10, pvd.find('"', at + 10) - at - 10)));
  REQUIRE(times.size() >= 3);
  const toml::table summary = toml::parse_file((out / "summary.toml").string());
  REQUIRE(summary["status"].value_or(std::string()) == "running");
  const double t = summary["time"].value_or(-1.0);
  INFO("summary time " << t << ", outputs " << times.size() << ", last at " << times.back());
  REQUIRE(t < 1.5e-6);
  const auto near = [&](double a) { return std::abs(t - a) <= 1e-9 * a; };
  REQUIRE((near(times.back()) || near(times[times.size() - 2])));
  REQUIRE(summary["steps"].value_or(0L) > 0);
}

TEST_CASE("a summary that cannot be written stops the run with an error naming it",
          "[unit][checkpoint]") {
  testing::TempFolder dir("summary_blocked");
  const fs::path out = dir.path / "run";
  fs::create_directories(out / "summary.toml.tmp");  // a folder where the file must go
  REQUIRE(shell(runCmd(sceneRun(out), dir.path / "log")) == 1);
  const std::string log = slurp(dir.path / "log");
  INFO(log);
  REQUIRE(log.find("cannot write " + (out / "summary.toml.tmp").string()) != std::string::npos);
  REQUIRE(log.find("run stopped at t = 0 s") != std::string::npos);
  REQUIRE(!fs::exists(out / "summary.toml"));
}

TEST_CASE("a run stopped by its time step floor names the cause and keeps valid files",
          "[unit][checkpoint]") {
  testing::TempFolder dir("dt_floor");
  const fs::path out = dir.path / "run";
  // The step falls from 16.5 ns to 6.5 ns when the first particle appears, near t = 0.33 us,
  // after the checkpoints at 0.1, 0.2 and 0.3 us and the outputs at 0 and 0.2 us.
  const std::string args = kScene + " --materials " + kLibrary + " --out " + out.string() +
                           " --set simulation.dt_min=8e-9 --set output.checkpoint_interval=0.1e-6"
                           " --set output.interval=0.2e-6";
  REQUIRE(shell(runCmd(args, dir.path / "log")) == 1);
  const std::string log = slurp(dir.path / "log");
  INFO(log);
  REQUIRE(log.find("below its floor") != std::string::npos);
  REQUIRE((log.find("limited by element") != std::string::npos ||
           log.find("limited by particle") != std::string::npos));
  REQUIRE(log.find("of body '") != std::string::npos);
  REQUIRE(log.find("at t = ") != std::string::npos);

  const std::vector<std::string> ckpts = listCheckpoints(out.string());
  REQUIRE(ckpts.size() == 2);  // the newest two are kept
  RunProgress progress;
  REQUIRE(readCheckpoint(ckpts.back(), progress).step > 0);
  // Every file the series lists is there and complete (no temporaries left).
  for (const char* pvd : {"elements.pvd", "particles.pvd"}) {
    const std::string text = slurp(out / pvd);
    std::size_t at = 0, listed = 0;
    while ((at = text.find("file=\"", at)) != std::string::npos) {
      at += 6;
      const std::string file = text.substr(at, text.find('"', at) - at);
      REQUIRE(fs::file_size(out / file) > 0);
      ++listed;
    }
    REQUIRE(listed >= 2);
  }
  for (const auto& e : fs::directory_iterator(out))
    REQUIRE(e.path().extension() != ".tmp");
  REQUIRE(shell("h5dump -H " + (out / "run.h5").string() + " > /dev/null") == 0);
}

TEST_CASE("a non-finite state stops the run naming the node, element, body and time",
          "[unit][checkpoint]") {
  const Scene scene = loadScene(kScene, {}, kLibrary);
  Model model = buildModel(scene);
  stepTo(model, 3);
  // A node of the projectile, free in z (no wall, no symmetry plane acts on it).
  const int node = model.elems.conn[model.bodies[0].elem_begin][0];
  model.nodes.v[node].z() = std::nan("");
  try {
    step(model, model.controls.end_time);
    FAIL("no error");
  } catch (const RunError& e) {
    const std::string what = e.what();
    INFO(what);
    // The first node in index order: this one or one that shares an element with it.
    const std::size_t at = what.find("non-finite velocity at node ");
    REQUIRE(at != std::string::npos);
    const int named = std::stoi(what.substr(at + 28));
    bool neighbour = named == node;
    for (const auto& c : model.elems.conn)
      neighbour = neighbour || (std::count(c.begin(), c.end(), node) &&
                                std::count(c.begin(), c.end(), named));
    REQUIRE(neighbour);
    REQUIRE(what.find("(element ") != std::string::npos);
    REQUIRE(what.find("of body 'projectile'") != std::string::npos);
    REQUIRE(what.find("at t = ") != std::string::npos);
  }
}

TEST_CASE("an energy budget that stops closing stops the run naming where", "[unit][checkpoint]") {
  const Scene scene = loadScene(kScene, {}, kLibrary);
  Model model = buildModel(scene);
  stepTo(model, 3);
  // A node of the projectile kicked to 40 times the shot's speed: finite, but the kinetic
  // energy jumps far past the 10 % the budget may miss.
  const int node = model.elems.conn[model.bodies[0].elem_begin][0];
  model.nodes.v[node] *= 40.0;
  try {
    step(model, model.controls.end_time);
    FAIL("no error");
  } catch (const RunError& e) {
    const std::string what = e.what();
    INFO(what);
    REQUIRE(what.find("energy balance error ") != std::string::npos);
    REQUIRE(what.find("gone unstable") != std::string::npos);
    REQUIRE(what.find("node " + std::to_string(node) + " of body 'projectile'") !=
            std::string::npos);
  }
}

TEST_CASE("missing, truncated and foreign checkpoints give clear errors", "[unit][checkpoint]") {
  testing::TempFolder dir("bad_checkpoints");
  const Scene scene = loadScene(kScene, {}, kLibrary);
  const Model model = buildModel(scene);
  const std::string good = (dir.path / "good.h5").string();
  writeCheckpoint(good, model, RunProgress{});

  SECTION("not a bad one: a checkpoint written before the first step reads back") {
    REQUIRE(model.step == 0);
    REQUIRE(checkpointError(good).empty());
  }
  SECTION("missing") {
    const std::string what = checkpointError((dir.path / "nope.h5").string());
    REQUIRE(what.find("nope.h5: no such file") != std::string::npos);
    // The command line reports it as bad input, exit code 2.
    REQUIRE(shell(runCmd("--restart " + (dir.path / "nope.h5").string(), dir.path / "log")) == 2);
    REQUIRE(slurp(dir.path / "log").find("no such file") != std::string::npos);
  }
  SECTION("truncated") {
    const std::string bytes = slurp(good);
    for (std::size_t keep : {bytes.size() / 2, bytes.size() - 1, std::size_t{100}}) {
      const std::string cut = (dir.path / "cut.h5").string();
      std::ofstream(cut, std::ios::binary) << bytes.substr(0, keep);
      const std::string what = checkpointError(cut);
      INFO(keep << " bytes: " << what);
      REQUIRE(what.rfind(cut + ":", 0) == 0);
      REQUIRE((what.find("truncated") != std::string::npos ||
               what.find("not an HDF5 file") != std::string::npos));
    }
  }
  SECTION("not HDF5") {
    const std::string text = (dir.path / "text.h5").string();
    std::ofstream(text) << "title = \"a scene, not a checkpoint\"\n";
    REQUIRE(checkpointError(text).find("not an HDF5 file") != std::string::npos);
  }
  SECTION("an HDF5 file of something else") {
    const std::string other = (dir.path / "other.h5").string();
    {
      const h5::Handle f = h5::openFile(other, h5::Mode::Create);
      h5::writeAttribute(f, "title", std::string("not ours"));
    }
    REQUIRE(checkpointError(other).find("not a fesph checkpoint") != std::string::npos);
  }
  SECTION("a checkpoint of another format version") {
    {
      const h5::Handle f = h5::openFile(good, h5::Mode::ReadWrite);
      h5::writeAttribute(f, "format_version", std::int64_t{1});
    }
    const std::string what = checkpointError(good);
    REQUIRE(what.find("checkpoint format version 1, this fesph reads versions 2 to") !=
            std::string::npos);
  }
  SECTION("a checkpoint with an array missing") {
    {
      const h5::Handle f = h5::openFile(good, h5::Mode::ReadWrite);
      REQUIRE(H5Ldelete(f.id(), "/elements/conn", H5P_DEFAULT) >= 0);
    }
    const std::string what = checkpointError(good);
    INFO(what);
    REQUIRE(what.find("/elements/conn") != std::string::npos);
    REQUIRE(what.find("missing") != std::string::npos);
  }
  SECTION("a checkpoint whose arrays do not fit together") {
    {
      const h5::Handle f = h5::openFile(good, h5::Mode::ReadWrite);
      REQUIRE(H5Ldelete(f.id(), "/nodes/m", H5P_DEFAULT) >= 0);
      const h5::Handle nodes = h5::openGroup(f, "nodes");
      const double one = 1.0;
      h5::writeArray(nodes, "m", H5T_NATIVE_DOUBLE, &one, 1, 1);
    }
    REQUIRE(checkpointError(good).find("inconsistent checkpoint: node arrays") !=
            std::string::npos);
  }
  SECTION("a checkpoint whose SPH snapshot arrays do not fit together") {
    {  // the snapshot of a model without particles is empty: one volume too many
      const h5::Handle f = h5::openFile(good, h5::Mode::ReadWrite);
      REQUIRE(H5Ldelete(f.id(), "/sph/current/V", H5P_DEFAULT) >= 0);
      const h5::Handle current = h5::openGroup(f, "sph/current");
      const double volume = 1e-9;
      h5::writeArray(current, "V", H5T_NATIVE_DOUBLE, &volume, 1, 1);
    }
    const std::string what = checkpointError(good);
    INFO(what);
    REQUIRE(what.find("inconsistent checkpoint: SPH snapshot arrays of different lengths") !=
            std::string::npos);
  }
}
