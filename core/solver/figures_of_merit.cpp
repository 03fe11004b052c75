// SPDX-License-Identifier: MIT
#include "core/solver/figures_of_merit.hpp"

#include "core/common/heap_bytes.hpp"
#include "core/conversion/particle_face_contact.hpp"

#include <sys/resource.h>

#include <string>

namespace fesph {

namespace {

template <class... T>
std::size_t bytes(const T&... containers) {
  return heapBytes(containers...);
}

std::size_t snapshotBytes(const SphSnapshot& s) {
  return bytes(s.x, s.v, s.h, s.V, s.volume_rate, s.rho, s.c, s.d, s.B, s.R, s.tensile);
}

}  // namespace

Footprint modelFootprint(const Model& m) {
  Footprint f;
  const Elements& el = m.elems;
  const Surfaces& s = m.surfaces;
  f.elements = bytes(el.conn, el.body, el.material, el.V0, el.V, el.dV, el.rho, el.q) +
               bytes(el.div_v, el.dt, el.len, el.len0, el.state, el.status, el.yield_cache, el.trigger) +
               bytes(m.corner_force, m.node_corners, s.table, s.elem_faces);
  const Nodes& nd = m.nodes;
  f.nodes = bytes(nd.x, nd.x0, nd.v, nd.f, nd.m, nd.body, nd.fix, m.node_corner_offset) +
            bytes(m.nodal_volume_ratio, m.v_node_free, s.node_face_count, s.node_slot);
  const ContactCandidates& c = s.candidates;
  const ContactScratch& w = s.scratch;
  f.contact = bytes(s.exterior, s.slave_nodes, c.slaves, c.body_begin, c.offset, c.faces) +
              bytes(c.active, w.face_lo, w.face_hi, w.face_tol, w.slave_lo, w.slave_hi) +
              bytes(w.queried, w.bucket_offset, w.bucket_fill, w.bucket_faces, w.thread_cells) +
              bytes(w.thread_faces, w.slave_thread, w.slave_start, w.contact_face);
  const Particles& pa = m.particles;
  const SphWorkspace& ws = m.sph;
  f.particles = bytes(pa.x, pa.v, pa.f, pa.m, pa.V, pa.rho, pa.h, pa.d0, pa.dt, pa.state) +
                bytes(pa.body, pa.material, pa.parent, pa.tie, pa.id, m.v_particle_free) +
                bytes(ws.neighbours.offset, ws.neighbours.index, ws.pair_grad) +
                bytes(ws.neighbours_last.offset, ws.neighbours_last.index, ws.pair_grad_last) +
                bytes(ws.pair_stab, ws.pair_stab_last, ws.pair_last_slot) +
                snapshotBytes(ws.current) + snapshotBytes(ws.previous) +
                bytes(ws.corrected, ws.velocity_grad, ws.velocity_grad_prev, ws.stress_b) +
                bytes(ws.plastic_work, ws.av_work, ws.internal_energy, ws.contact_radius) +
                bytes(ws.contact_spacing, ws.contact_pairs, ws.yield_cache, ws.mirrors) +
                ws.search.bytes() + particleFaceContactScratchBytes();
  for (const MirrorImage& mi : ws.mirrors)
    f.particles += bytes(mi.neighbours.offset, mi.neighbours.index, mi.grad, mi.grad_prev) +
                   bytes(mi.contact.offset, mi.contact.index);
  return f;
}

std::size_t peakResidentBytes() {
  rusage u{};
  if (getrusage(RUSAGE_SELF, &u) != 0) return 0;
  return static_cast<std::size_t>(u.ru_maxrss) * 1024;  // Linux: kilobytes
}

void printFiguresOfMerit(const Model& model, std::FILE* out) {
  const PhaseTimes& t = model.timing;
  const double total = t.total();
  if (t.element_steps > 0)
    std::fprintf(out, "  element phase    %.1f ns per element-step (%.4g element-steps)\n",
                 1e9 * t.seconds[static_cast<int>(Phase::Elements)] / t.element_steps,
                 t.element_steps);
  if (t.particle_steps > 0)
    std::fprintf(out, "  particle phase   %.1f ns per particle-step (%.4g particle-steps)\n",
                 1e9 * t.seconds[static_cast<int>(Phase::Particles)] / t.particle_steps,
                 t.particle_steps);
  // Verlet lists: a build per step would mean the skin buys nothing.
  if (t.particle_steps > 0)
    std::fprintf(out,
                 "  neighbour lists  %ld SPH, %ld contact and %ld mirror builds in %ld steps, %ld "
                 "particles re-seated\n",
                 model.sph.search.verletBuilds(), model.sph.search.contactVerletBuilds(),
                 model.sph.search.mirrorVerletBuilds(), t.steps, model.sph.search.verletReseats());
  if (total > 0) {
    std::string split;
    for (int p = 0; p < static_cast<int>(Phase::Count); ++p) {
      if (t.seconds[p] <= 0) continue;
      char item[64];
      std::snprintf(item, sizeof item, "%s%s %.1f %%", split.empty() ? "" : ", ",
                    phaseName(static_cast<Phase>(p)), 100 * t.seconds[p] / total);
      split += item;
    }
    std::fprintf(out, "  time by phase    %s\n", split.c_str());
  }
  const Footprint f = modelFootprint(model);
  const double mb = 1.0 / (1024.0 * 1024.0);
  std::fprintf(out, "  memory           peak resident %.1f MB; model arrays %.1f MB",
               mb * static_cast<double>(peakResidentBytes()), mb * static_cast<double>(f.total()));
  if (!model.elems.conn.empty())
    std::fprintf(out, " (%.0f B per element",
                 static_cast<double>(f.elements + f.nodes + f.contact) /
                     static_cast<double>(model.elems.size()));
  if (!model.particles.x.empty())
    std::fprintf(out, "%s%.0f B per particle", model.elems.conn.empty() ? " (" : ", ",
                 static_cast<double>(f.particles) / static_cast<double>(model.particles.size()));
  if (!model.elems.conn.empty() || !model.particles.x.empty()) std::fprintf(out, ")");
  std::fprintf(out, "\n");
}

}  // namespace fesph
