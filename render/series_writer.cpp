// SPDX-License-Identifier: MIT
// ParaView time series writers: VTK 9.1 XML files (appended raw binary, zlib, UInt64 headers)
// and the .pvd collections that list them.
#include "render/series_writer.hpp"

#include "core/common/error.hpp"
#include "core/common/number_text.hpp"
#include "core/common/read_file.hpp"
#include "core/io/replace_file.hpp"
#include "core/scene/scene.hpp"
#include "render/vtk_errors.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>
#include <vtkXMLWriter.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace fesph {

namespace fs = std::filesystem;

namespace {

// A plain file name cannot escape the folder and needs no XML escaping.
bool isPlainFileName(const std::string& name) {
  return !name.empty() && name != "." && name != ".." &&
         name.find_first_of("/\\&<>\"'") == std::string::npos;
}

// Value of attribute `name` inside one XML tag, or false when it is absent.
bool attribute(const std::string& tag, const std::string& name, std::string& value) {
  const std::string key = name + "=\"";
  std::size_t at = 0;
  while ((at = tag.find(key, at)) != std::string::npos) {
    // Match whole attribute names only ("file" must not match "xfile").
    if (at > 0 && !std::isspace(static_cast<unsigned char>(tag[at - 1]))) {
      at += key.size();
      continue;
    }
    const std::size_t begin = at + key.size();
    const std::size_t end = tag.find('"', begin);
    if (end == std::string::npos) return false;
    value = tag.substr(begin, end - begin);
    return true;
  }
  return false;
}

std::vector<PvdCollection::Entry> readPvd(const fs::path& path) {
  std::string text, why;
  if (!readWholeFile(path.string(), text, why))
    throw RunError("cannot read " + path.string() + ": " + why);

  std::vector<PvdCollection::Entry> entries;
  std::size_t at = 0;
  while ((at = text.find("<DataSet", at)) != std::string::npos) {
    const std::size_t end = text.find('>', at);
    if (end == std::string::npos) throw RunError(path.string() + ": unterminated <DataSet");
    const std::string tag = text.substr(at, end - at);
    at = end;
    std::string time, file;
    if (!attribute(tag, "timestep", time) || !attribute(tag, "file", file))
      throw RunError(path.string() + ": <DataSet> without timestep or file: " + tag);
    double t = 0;
    const auto res = std::from_chars(time.data(), time.data() + time.size(), t);
    if (res.ec != std::errc() || res.ptr != time.data() + time.size())
      throw RunError(path.string() + ": bad timestep \"" + time + "\"");
    entries.push_back({t, file});
  }
  return entries;
}

// VTK 9.1 XML output as recommended for ParaView 5.11 (paraview.md, section 4), written under
// a temporary name and renamed into place.
void writeXml(vtkXMLWriter& w, const fs::path& target) {
  w.SetDataModeToAppended();
  w.EncodeAppendedDataOff();  // raw bytes, not base64
  w.SetCompressorTypeToZLib();
  w.SetHeaderTypeToUInt64();  // block headers safe beyond 4 GiB
  const fs::path tmp = temporaryFor(target.string());
  w.SetFileName(tmp.c_str());
  clearVtkError();
  if (w.Write() != 1 || w.GetErrorCode() != 0) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw RunError(cannotWrite(target.string(), w.GetErrorCode()));
  }
  renameInto(tmp.string(), target.string());
}

vtkNew<vtkDoubleArray> doubleArray(const char* name, int components, vtkIdType tuples) {
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  return a;
}

void addTimeValue(vtkDataObject& data, double time) {
  vtkNew<vtkDoubleArray> t;
  t->SetName("TimeValue");
  t->InsertNextValue(time);
  data.GetFieldData()->AddArray(t);
}


std::string indexedName(const char* stem, std::size_t index, const char* extension) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s_%06zu.%s", stem, index, extension);
  return buf;
}

}  // namespace

// ---- PvdCollection -----------------------------------------------------------------------

PvdCollection::PvdCollection(fs::path pvd_path, bool append, std::size_t keep)
    : path_(std::move(pvd_path)) {
  if (!fs::exists(path_)) return;
  if (append) {
    entries_ = readPvd(path_);
    if (entries_.size() > keep) {
      entries_.resize(keep);
      save();
    }
    return;
  }
  // A fresh series must not leave steps of the previous run behind for ParaView to show.
  std::vector<Entry> old;
  try {
    old = readPvd(path_);
  } catch (const RunError&) {
    // a damaged .pvd of an earlier run is simply replaced
  }
  fs::remove(path_);
  for (const Entry& e : old)
    if (isPlainFileName(e.file)) fs::remove(path_.parent_path() / e.file);
}

void PvdCollection::add(double time, const std::string& file) {
  if (!isPlainFileName(file))
    throw std::invalid_argument("PvdCollection: \"" + file + "\" is not a plain file name");
  entries_.push_back({time, file});
  try {
    save();
  } catch (...) {
    entries_.pop_back();
    throw;
  }
}

void PvdCollection::save() const {
  const fs::path tmp = temporaryFor(path_.string());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << "<?xml version=\"1.0\"?>\n"
           "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
           "  <Collection>\n";
    for (const Entry& e : entries_)
      out << "    <DataSet timestep=\"" << shortestText(e.time) << "\" part=\"0\" file=\""
          << e.file << "\"/>\n";
    out << "  </Collection>\n"
           "</VTKFile>\n";
    out.close();
    if (!out) {
      std::error_code ignored;
      fs::remove(tmp, ignored);
      throw RunError("cannot write " + path_.string());
    }
  }
  renameInto(tmp.string(), path_.string());
}

// ---- SeriesWriter ------------------------------------------------------------------------

namespace {

std::vector<std::string> checkedFields(std::vector<std::string> fields) {
  for (const std::string& f : fields)
    if (const std::string error = outputFieldError(f); !error.empty())
      throw std::invalid_argument(error);
  return fields;
}

fs::path createdFolder(fs::path folder) {
  fs::create_directories(folder);
  return folder;
}

}  // namespace

const std::vector<std::string>& SeriesWriter::elementFields() { return outputFieldNames(); }

SeriesWriter::SeriesWriter(fs::path folder, SeriesOptions options)
    : folder_(createdFolder(std::move(folder))),
      fields_(checkedFields(std::move(options.fields))),
      material_names_(std::move(options.material_names)),
      elements_(folder_ / "elements.pvd", options.append, options.keep),
      particles_(folder_ / "particles.pvd", options.append, options.keep) {}

// What the values of the "material" arrays stand for: entry k names material k.
void SeriesWriter::addMaterialNames(vtkDataObject& data, const Model& model) const {
  vtkNew<vtkStringArray> names;
  names->SetName("material_names");
  for (std::size_t k = 0; k < model.materials.size(); ++k)
    names->InsertNextValue(k < material_names_.size() ? material_names_[k]
                                                      : model.materials[k].name);
  data.GetFieldData()->AddArray(names);
}

bool SeriesWriter::wants(const std::string& field) const {
  // What fesph's own images read (plates: body and damage; section: plastic strain) is written
  // whatever the list: a run limited to "pressure" drew no image at its end.
  static const std::array<std::string, 3> kViews = {"body", "damage", "plastic_strain"};
  return fields_.empty() || std::find(fields_.begin(), fields_.end(), field) != fields_.end() ||
         std::find(kViews.begin(), kViews.end(), field) != kViews.end();
}

void SeriesWriter::write(const Model& model, double time) {
  const Nodes& nodes = model.nodes;
  const Elements& elems = model.elems;

  std::vector<vtkIdType> live;
  for (std::size_t e = 0; e < elems.size(); ++e)
    if (elems.status[e] == ElemStatus::Live) live.push_back(static_cast<vtkIdType>(e));

  // Compact the points to the nodes of live elements, in node order.
  std::vector<vtkIdType> local(nodes.size(), -1);
  for (vtkIdType e : live)
    for (int n : elems.conn[e]) local[n] = 0;
  std::vector<vtkIdType> used;
  for (std::size_t n = 0; n < nodes.size(); ++n)
    if (local[n] == 0) {
      local[n] = static_cast<vtkIdType>(used.size());
      used.push_back(static_cast<vtkIdType>(n));
    }
  const auto np = static_cast<vtkIdType>(used.size());
  const auto nc = static_cast<vtkIdType>(live.size());

  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(np);
  for (vtkIdType i = 0; i < np; ++i) {
    const Vec3& x = nodes.x[used[i]];
    points->SetPoint(i, x.x(), x.y(), x.z());
  }
  grid->SetPoints(points);

  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfValues(4 * nc);
  for (vtkIdType c = 0; c < nc; ++c)
    for (int k = 0; k < 4; ++k) connectivity->SetValue(4 * c + k, local[elems.conn[live[c]][k]]);
  vtkNew<vtkCellArray> cells;
  cells->SetData(4, connectivity);
  grid->SetCells(VTK_TETRA, cells);

  vtkCellData* cd = grid->GetCellData();
  if (wants("stress")) {
    auto a = doubleArray("stress", 6, nc);
    // ParaView's symmetric tensor order: XX YY ZZ XY YZ XZ.
    const char* names[6] = {"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
    for (int k = 0; k < 6; ++k) a->SetComponentName(k, names[k]);
    for (vtkIdType c = 0; c < nc; ++c) {
      const PointState& st = elems.state[live[c]];
      const double sigma[6] = {st.s.xx - st.p, st.s.yy - st.p, st.s.zz - st.p,
                               st.s.xy,        st.s.yz,        st.s.zx};
      a->SetTypedTuple(c, sigma);
    }
    cd->AddArray(a);
  }
  // One Float64 cell array per scalar of the element state.
  const auto scalar = [&](const char* name, auto value) {
    if (!wants(name)) return;
    auto a = doubleArray(name, 1, nc);
    for (vtkIdType c = 0; c < nc; ++c) a->SetValue(c, value(live[c]));
    cd->AddArray(a);
  };
  scalar("pressure", [&](vtkIdType e) { return elems.state[e].p; });
  scalar("von_mises", [&](vtkIdType e) { return vonMises(elems.state[e].s); });
  scalar("plastic_strain", [&](vtkIdType e) { return elems.state[e].eps_p; });
  scalar("plastic_strain_rate", [&](vtkIdType e) { return elems.state[e].eps_rate; });
  scalar("temperature", [&](vtkIdType e) { return elems.state[e].T; });
  scalar("damage", [&](vtkIdType e) { return elems.state[e].damage; });
  scalar("density", [&](vtkIdType e) { return elems.rho[e]; });
  if (wants("body")) {
    vtkNew<vtkIntArray> a;
    a->SetName("body");
    a->SetNumberOfValues(nc);
    for (vtkIdType c = 0; c < nc; ++c) a->SetValue(c, elems.body[live[c]]);
    cd->AddArray(a);
  }
  if (wants("material")) {  // a body meshed of several volumes has several
    vtkNew<vtkIntArray> a;
    a->SetName("material");
    a->SetNumberOfValues(nc);
    for (vtkIdType c = 0; c < nc; ++c) a->SetValue(c, elems.material[live[c]]);
    cd->AddArray(a);
    addMaterialNames(*grid, model);
  }
  if (wants("element_id")) {
    vtkNew<vtkTypeInt64Array> a;
    a->SetName("element_id");
    a->SetNumberOfValues(nc);
    for (vtkIdType c = 0; c < nc; ++c) a->SetValue(c, live[c]);
    cd->AddArray(a);
  }

  vtkPointData* pd = grid->GetPointData();
  const auto vector = [&](const char* name, auto value) {
    if (!wants(name)) return;
    auto a = doubleArray(name, 3, np);
    for (vtkIdType i = 0; i < np; ++i) {
      const Vec3 v = value(used[i]);
      a->SetTypedTuple(i, v.data());
    }
    pd->AddArray(a);
  };
  vector("velocity", [&](vtkIdType n) { return nodes.v[n]; });
  vector("displacement", [&](vtkIdType n) -> Vec3 { return nodes.x[n] - nodes.x0[n]; });
  if (wants("node_id")) {
    vtkNew<vtkTypeInt64Array> a;
    a->SetName("node_id");
    a->SetNumberOfValues(np);
    for (vtkIdType i = 0; i < np; ++i) a->SetValue(i, used[i]);
    pd->AddArray(a);
  }

  addTimeValue(*grid, time);

  const std::string file = indexedName("elements", outputCount(), "vtu");
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetInputData(grid);
  writeXml(*writer, folder_ / file);
  elements_.add(time, file);
  writeParticles(model, time);
}

void SeriesWriter::writeParticles(const Model& model, double time) {
  const Particles& pa = model.particles;
  const auto n = static_cast<vtkIdType>(pa.size());
  vtkNew<vtkPolyData> poly;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  vtkNew<vtkCellArray> verts;
  for (vtkIdType i = 0; i < n; ++i) {
    points->SetPoint(i, pa.x[i].x(), pa.x[i].y(), pa.x[i].z());
    verts->InsertNextCell(1, &i);
  }
  poly->SetPoints(points);
  poly->SetVerts(verts);

  vtkPointData* pd = poly->GetPointData();
  auto scalar = [&](const char* name, auto value) {
    vtkNew<vtkDoubleArray> a = doubleArray(name, 1, n);
    for (vtkIdType i = 0; i < n; ++i) a->SetValue(i, value(i));
    pd->AddArray(a);
  };
  scalar("radius", [&](vtkIdType i) { return particleRadius(pa, static_cast<std::size_t>(i)); });
  scalar("mass", [&](vtkIdType i) { return pa.m[i]; });
  scalar("density", [&](vtkIdType i) { return pa.rho[i]; });
  scalar("pressure", [&](vtkIdType i) { return pa.state[i].p; });
  scalar("von_mises", [&](vtkIdType i) { return vonMises(pa.state[i].s); });
  scalar("plastic_strain", [&](vtkIdType i) { return pa.state[i].eps_p; });
  scalar("plastic_strain_rate", [&](vtkIdType i) { return pa.state[i].eps_rate; });
  scalar("damage", [&](vtkIdType i) { return pa.state[i].damage; });
  scalar("temperature", [&](vtkIdType i) { return pa.state[i].T; });
  scalar("tied", [&](vtkIdType i) { return pa.tie[i].active() ? 1.0 : 0.0; });
  vtkNew<vtkDoubleArray> vel = doubleArray("velocity", 3, n);
  for (vtkIdType i = 0; i < n; ++i) vel->SetTuple3(i, pa.v[i].x(), pa.v[i].y(), pa.v[i].z());
  pd->AddArray(vel);
  vtkNew<vtkIntArray> body;
  body->SetName("body");
  body->SetNumberOfValues(n);
  for (vtkIdType i = 0; i < n; ++i) body->SetValue(i, pa.body[i]);
  pd->AddArray(body);
  vtkNew<vtkIntArray> material;
  material->SetName("material");
  material->SetNumberOfValues(n);
  for (vtkIdType i = 0; i < n; ++i) material->SetValue(i, pa.material[i]);
  pd->AddArray(material);
  addMaterialNames(*poly, model);
  vtkNew<vtkTypeInt64Array> parent;
  parent->SetName("parent_element");
  parent->SetNumberOfValues(n);
  for (vtkIdType i = 0; i < n; ++i) parent->SetValue(i, pa.parent[i]);
  pd->AddArray(parent);
  vtkNew<vtkTypeInt64Array> id;  // the particles are renumbered during a run: follow this
  id->SetName("particle_id");
  id->SetNumberOfValues(n);
  for (vtkIdType i = 0; i < n; ++i) id->SetValue(i, pa.id[i]);
  pd->AddArray(id);
  addTimeValue(*poly, time);

  const std::string file = indexedName("particles", particles_.entries().size(), "vtp");
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(poly);
  writeXml(*writer, folder_ / file);
  particles_.add(time, file);
}

}  // namespace fesph
