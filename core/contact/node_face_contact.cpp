// SPDX-License-Identifier: MIT
#include "core/contact/node_face_contact.hpp"

#include "core/contact/broad_phase.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fesph {

namespace {

// A slave over an edge or a vertex is held by the faces around it, within this slack on the
// barycentric weights (each of them then takes part of the correction).
constexpr double kEdgeSlack = 1e-3;

struct Hit {
  double delta = 0;     ///< predicted penetration, m
  double approach = 0;  ///< how far it moves into the face over the step, m
  Vec3 n = Vec3::Zero();  ///< outward unit normal of the face at the predicted positions
  std::array<double, 3> R = {0, 0, 0};  ///< barycentric weights of the slave's projection
};

// Would slave node a, with the velocities as they are now, end the step behind face f, within
// it, having started the step in front of it (or behind it by less than tol)?
bool probe(const Nodes& nd, int a, const ExteriorFace& f, double tol, double dt, Hit& hit) {
  const Vec3 ya = nd.x[a] + dt * nd.v[a];
  const std::array<Vec3, 3> y = {nd.x[f.node[0]] + dt * nd.v[f.node[0]],
                                 nd.x[f.node[1]] + dt * nd.v[f.node[1]],
                                 nd.x[f.node[2]] + dt * nd.v[f.node[2]]};
  const Vec3 N = (y[1] - y[0]).cross(y[2] - y[0]);
  const double NN = N.squaredNorm();
  if (!(NN > 0)) return false;
  const double gap = (ya - y[0]).dot(N) / std::sqrt(NN);
  if (gap >= 0) return false;

  // The side it started on: a node far behind the face came through elsewhere.
  const Vec3& x0 = nd.x[f.node[0]];
  const Vec3 N0 = (nd.x[f.node[1]] - x0).cross(nd.x[f.node[2]] - x0);
  const double gap0 = (nd.x[a] - x0).dot(N0) / N0.norm();
  if (gap0 < -tol) return false;
  // A node already (slightly) behind is kept from going deeper, not pushed out: near a
  // convex edge it is "behind" the face round the corner, which it is not moving into.
  const double delta = -gap + std::min(gap0, 0.0);
  if (!(delta > 0)) return false;

  const Vec3 n = N / std::sqrt(NN);
  const Vec3 p = ya - gap * n;
  std::array<double, 3> R = {(y[1] - p).cross(y[2] - p).dot(N) / NN,
                             (y[2] - p).cross(y[0] - p).dot(N) / NN, 0.0};
  R[2] = 1.0 - R[0] - R[1];
  if (std::min({R[0], R[1], R[2]}) < -kEdgeSlack) return false;
  double sum = 0;
  for (double& r : R) sum += (r = std::max(r, 0.0));
  for (double& r : R) r /= sum;

  hit.delta = delta;
  hit.approach = gap0 - gap;
  hit.n = n;
  hit.R = R;
  return true;
}

// Paper eqs. 1-4 written with the impulse P on the slave (and -R_i P on the face nodes):
// P (1/m_s + sum R_i^2/m_i) = alpha delta/dt changes the normal approach rate by alpha delta/dt,
// i.e. dv_s = alpha (delta/dt) / (1 + sum R_i^2 m_s/m_i), dv_i = -R_i m_s dv_s / m_i.
// Friction: the tangential impulse that stops the relative sliding, capped at mu P.
void correct(Nodes& nd, int a, const ExteriorFace& f, const Hit& hit,
             double alpha, double mu, double dt) {
  const double ws = nd.inverseMass(a);
  std::array<double, 3> wi;
  double denom = ws;
  for (int i = 0; i < 3; ++i) {
    wi[i] = nd.inverseMass(f.node[i]);
    denom += hit.R[i] * hit.R[i] * wi[i];
  }
  if (!(denom > 0)) return;
  const double P = alpha * hit.delta / dt / denom;
  Vec3 impulse = P * hit.n;
  if (mu > 0) {
    Vec3 v_rel = nd.v[a] + ws * impulse;
    for (int i = 0; i < 3; ++i)
      v_rel -= hit.R[i] * (nd.v[f.node[i]] - hit.R[i] * wi[i] * impulse);
    const Vec3 v_t = v_rel - v_rel.dot(hit.n) * hit.n;
    const double vt_norm = v_t.norm();
    if (vt_norm > 0) impulse -= std::min(vt_norm / denom, mu * P) / vt_norm * v_t;
  }
  nd.addVelocity(a, ws * impulse);
  for (int i = 0; i < 3; ++i) nd.addVelocity(f.node[i], (-hit.R[i] * wi[i]) * impulse);
}

}  // namespace

void enforceNodeFaceContact(Model& model, double dt, const ContactControls& controls) {
  Surfaces& s = model.surfaces;
  if (!(dt > 0) || s.exterior.empty() || controls.passes < 1) return;
  findContactCandidates(model, dt, controls.depth_tolerance);
  const ContactCandidates& cand = s.candidates;
  if (cand.faces.empty()) return;
  Nodes& nd = model.nodes;
  ContactScratch& w = s.scratch;
  const std::vector<double>& face_tol = w.face_tol;
  std::vector<int>& contact_face = w.contact_face;
  const std::vector<int>& active = cand.active;  // the slaves with candidates, ascending
  contact_face.assign(active.size(), -1);

  const int N = controls.passes;
  for (int k = 1; k <= N; ++k) {
    const double alpha = 1.0 / std::sqrt(static_cast<double>(N - k + 1));
    bool corrected = false;
    for (std::size_t b = 0; b + 1 < cand.body_begin.size(); ++b) {
      // Body b's active slaves: active[begin, end).
      const auto first = [&](std::size_t slave) {
        return static_cast<std::size_t>(
            std::lower_bound(active.begin(), active.end(), static_cast<int>(slave)) -
            active.begin());
      };
      const std::size_t begin = first(cand.body_begin[b]), end = first(cand.body_begin[b + 1]);
      // Find, in parallel, the face each slave of body b moves into fastest: the one it is
      // crossing (a node on an edge also grazes the faces on the other side of it)... Dynamic:
      // the slaves' candidate counts differ, and each slave's answer has its own slot.
#pragma omp parallel for schedule(dynamic, 64) if (end - begin > 256)
      for (std::size_t j = begin; j < end; ++j) {
        const std::size_t i = static_cast<std::size_t>(active[j]);
        int best = -1;
        double best_approach = -std::numeric_limits<double>::infinity();
        for (std::size_t q = cand.offset[i]; q < cand.offset[i + 1]; ++q) {
          const int f = cand.faces[q];
          Hit hit;
          if (probe(nd, cand.slaves[i], s.exterior[f], face_tol[f], dt, hit) &&
              hit.approach > best_approach) {
            best = f;
            best_approach = hit.approach;
          }
        }
        contact_face[j] = best;
      }
      // ...then correct in slave order, each against the velocities the earlier ones left.
      for (std::size_t j = begin; j < end; ++j) {
        const std::size_t i = static_cast<std::size_t>(active[j]);
        const int f = contact_face[j];
        Hit hit;
        if (f < 0 || !probe(nd, cand.slaves[i], s.exterior[f], face_tol[f], dt, hit)) continue;
        correct(nd, cand.slaves[i], s.exterior[f], hit, alpha, controls.friction, dt);
        corrected = true;
      }
    }
    if (!corrected) break;  // nothing changed: later passes would find nothing either
  }
}

}  // namespace fesph
