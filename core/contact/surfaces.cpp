// SPDX-License-Identifier: MIT
#include "core/contact/surfaces.hpp"

#include "core/common/error.hpp"
#include "core/mesh/tet_faces.hpp"

#include <algorithm>
#include <string>

namespace fesph {

namespace {

std::array<int, 3> sortedKey(int a, int b, int c) {
  std::array<int, 3> k = {a, b, c};
  std::sort(k.begin(), k.end());
  return k;
}

void addSlaveReference(Surfaces& s, const Model& model, int node) {
  if (s.node_face_count[node]++ > 0) return;
  std::vector<int>& list = s.slave_nodes[model.nodes.body[node]];
  s.node_slot[node] = static_cast<int>(list.size());
  list.push_back(node);
}

void dropSlaveReference(Surfaces& s, const Model& model, int node) {
  if (--s.node_face_count[node] > 0) return;
  std::vector<int>& list = s.slave_nodes[model.nodes.body[node]];
  const int slot = s.node_slot[node];
  list[slot] = list.back();  // swap-remove: O(1)
  s.node_slot[list[slot]] = slot;
  list.pop_back();
  s.node_slot[node] = -1;
}

void addExterior(Surfaces& s, const Model& model, int f, int owner) {
  const auto& conn = model.elems.conn[owner];
  int k = 0;
  while (s.elem_faces[owner][k] != f) ++k;
  ExteriorFace ef;
  ef.node = tetFace(conn, k);
  ef.elem = owner;
  ef.body = model.elems.body[owner];
  ef.face = f;
  s.table[f].exterior = static_cast<int>(s.exterior.size());
  s.exterior.push_back(ef);
  for (int a : ef.node) addSlaveReference(s, model, a);
}

void removeExterior(Surfaces& s, const Model& model, int f) {
  const int i = s.table[f].exterior;
  const ExteriorFace gone = s.exterior[i];
  s.exterior[i] = s.exterior.back();  // swap-remove: O(1)
  s.table[s.exterior[i].face].exterior = i;
  s.exterior.pop_back();
  s.table[f].exterior = -1;
  for (int a : gone.node) dropSlaveReference(s, model, a);
}

// Bring face f to the state its elements' status asks for: exterior, owned by its only live
// element, or not exterior.
void refreshFace(Surfaces& s, const Model& model, int f) {
  const FaceRecord& rec = s.table[f];
  auto live = [&](int e) { return e >= 0 && model.elems.status[e] == ElemStatus::Live; };
  const bool l0 = live(rec.elem[0]), l1 = live(rec.elem[1]);
  const int want = l0 == l1 ? -1 : (l0 ? rec.elem[0] : rec.elem[1]);
  const int have = rec.exterior >= 0 ? s.exterior[rec.exterior].elem : -1;
  if (want == have) return;
  if (have >= 0) removeExterior(s, model, f);
  if (want >= 0) addExterior(s, model, f, want);
}

}  // namespace

void buildSurfaces(Model& model) {
  const Elements& el = model.elems;
  Surfaces& s = model.surfaces;
  s = Surfaces{};

  // Equal keys are neighbours, in element order.
  const std::vector<TetFaceEntry> entries = sortedTetFaces(el.conn);

  s.elem_faces.assign(el.size(), {-1, -1, -1, -1});
  for (std::size_t i = 0; i < entries.size();) {
    std::size_t j = i + 1;
    while (j < entries.size() && entries[j].key == entries[i].key) ++j;
    if (j - i > 2)
      throw InputError("", 0, 0,
                       "face of nodes " + std::to_string(entries[i].key[0]) + ", " +
                           std::to_string(entries[i].key[1]) + ", " +
                           std::to_string(entries[i].key[2]) + " is shared by " +
                           std::to_string(j - i) + " tetrahedra");
    FaceRecord rec;
    rec.key = entries[i].key;
    const int f = static_cast<int>(s.table.size());
    for (std::size_t m = i; m < j; ++m) {
      rec.elem[m - i] = entries[m].tet;
      s.elem_faces[entries[m].tet][entries[m].k] = f;
    }
    s.table.push_back(rec);
    i = j;
  }

  s.slave_nodes.assign(model.bodies.size(), {});
  s.node_face_count.assign(model.nodes.size(), 0);
  s.node_slot.assign(model.nodes.size(), -1);
  for (std::size_t f = 0; f < s.table.size(); ++f) refreshFace(s, model, static_cast<int>(f));
}

void removeElementFromSurfaces(Model& model, std::size_t e) {
  Surfaces& s = model.surfaces;
  for (int f : s.elem_faces[e]) refreshFace(s, model, f);
}

int findFace(const Surfaces& surfaces, int a, int b, int c) {
  const std::array<int, 3> key = sortedKey(a, b, c);
  const auto it = std::lower_bound(
      surfaces.table.begin(), surfaces.table.end(), key,
      [](const FaceRecord& r, const std::array<int, 3>& k) { return r.key < k; });
  return it != surfaces.table.end() && it->key == key
             ? static_cast<int>(it - surfaces.table.begin())
             : -1;
}

}  // namespace fesph
