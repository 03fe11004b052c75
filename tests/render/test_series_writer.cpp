// SPDX-License-Identifier: MIT
// SeriesWriter: writes a 3-step series of a hand-built two-body model and reads it back with
// VTK's XML reader (live cells only, arrays, exact values, times, .pvd, no temporary files).
#include "render/series_writer.hpp"
#include "render/vtk_errors.hpp"

#include "core/state/model_build.hpp"
#include "tests/support/temp_folder.hpp"
#include "tests/support/text.hpp"

#include <catch2/catch.hpp>

#include <vtkCellData.h>
#include <vtkErrorCode.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cerrno>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

using namespace fesph;
using fesph::testing::slurp;
using fesph::testing::TempFolder;
namespace fs = std::filesystem;

namespace {

void addTet(Model& m, std::array<int, 4> c, int body) {
  const Vec3& a = m.nodes.x0[c[0]];
  const double det = (m.nodes.x0[c[1]] - a).cross(m.nodes.x0[c[2]] - a).dot(m.nodes.x0[c[3]] - a);
  if (det < 0) std::swap(c[2], c[3]);
  m.elems.conn.push_back(c);
  m.elems.body.push_back(body);
  m.elems.material.push_back(static_cast<int>(m.elems.material.size() % 2));  // both kinds
  m.elems.V0.push_back(std::abs(det) / 6.0);
  m.elems.V.push_back(std::abs(det) / 6.0);
  m.elems.dV.push_back(0.0);
  m.elems.rho.push_back(7800.0);
  m.elems.q.push_back(0.0);
  m.elems.div_v.push_back(0.0);
  m.elems.dt.push_back(1e-7);
  m.elems.state.emplace_back();
  m.elems.status.push_back(ElemStatus::Live);
}

void addNode(Model& m, const Vec3& x0, int body) {
  m.nodes.x.push_back(x0);
  m.nodes.x0.push_back(x0);
  m.nodes.v.push_back(Vec3::Zero());
  m.nodes.f.push_back(Vec3::Zero());
  m.nodes.m.push_back(1.0);
  m.nodes.body.push_back(body);
  m.nodes.fix.push_back(0);
}

/// Body 0: unit cube cut into 5 tets (nodes 0-7, elements 0-4), element 0 converted, so node 0
/// is used by no live element. Body 1: two tets sharing a face (nodes 8-12, elements 5-6),
/// element 6 eroded, so node 12 is unused. Live: 4 + 1 = 5 cells on 11 points.
Model twoBodies() {
  Model m;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) addNode(m, Vec3(i, j, k), 0);
  for (const auto& c : {std::array<int, 4>{0, 1, 2, 4}, {3, 2, 1, 7}, {5, 1, 4, 7},
                        {6, 4, 2, 7}, {1, 2, 4, 7}})
    addTet(m, c, 0);
  addNode(m, Vec3(3, 0, 0), 1);
  addNode(m, Vec3(4, 0, 0), 1);
  addNode(m, Vec3(3, 1, 0), 1);
  addNode(m, Vec3(3, 0, 1), 1);
  addNode(m, Vec3(4, 1, 1), 1);
  addTet(m, {8, 9, 10, 11}, 1);
  addTet(m, {9, 10, 11, 12}, 1);
  m.elems.status[0] = ElemStatus::Converted;
  m.elems.status[6] = ElemStatus::Eroded;

  Body b0, b1;
  b0.name = "cube";
  b0.node_end = 8;
  b0.elem_end = 5;
  b1.name = "wedge";
  b1.node_begin = 8;
  b1.node_end = 13;
  b1.elem_begin = 5;
  b1.elem_end = 7;
  m.bodies = {b0, b1};
  m.materials.resize(2);
  m.materials[0].name = "steel core";
  m.materials[1].name = "copper jacket";
  return m;
}

/// Values that differ per node, element and step, with bits that text output would lose.
void setStep(Model& m, int step) {
  for (std::size_t n = 0; n < m.nodes.size(); ++n) {
    const double a = 0.1 * step + n / 3.0;
    m.nodes.x[n] = m.nodes.x0[n] + Vec3(1e-3 * a, -2e-3 * a, 0.0);
    m.nodes.v[n] = Vec3(a, -a / 7.0, 1.0 / (n + 1.0));
  }
  for (std::size_t e = 0; e < m.elems.size(); ++e) {
    PointState& st = m.elems.state[e];
    const double a = step + e / 3.0;
    st.s = Sym{1e6 * a, -2e6 * a, 1e6 * a, 3e5 * a, -4e5 * a, 5e5 * a};
    st.p = 1e7 * a + 0.1;
    st.eps_p = 0.01 * a;
    st.eps_rate = 1e3 * a;
    st.T = 293.0 + a;
    st.damage = 0.05 * a;
    m.elems.rho[e] = 7800.0 + a;
  }
}

vtkSmartPointer<vtkUnstructuredGrid> readVtu(const fs::path& file) {
  auto reader = vtkSmartPointer<vtkXMLUnstructuredGridReader>::New();
  reader->SetFileName(file.c_str());
  reader->Update();
  REQUIRE(reader->GetErrorCode() == 0);
  return reader->GetOutput();
}


/// Text between `key="` and the next quote, searching from `at`.
std::string quoted(const std::string& text, const std::string& key, std::size_t at) {
  const std::size_t begin = text.find(key + "=\"", at) + key.size() + 2;
  return text.substr(begin, text.find('"', begin) - begin);
}

/// (timestep, file) attribute pairs of the .pvd, as text (independent of PvdCollection).
std::vector<std::pair<std::string, std::string>> pvdEntries(const fs::path& pvd) {
  const std::string text = slurp(pvd);
  std::vector<std::pair<std::string, std::string>> out;
  for (std::size_t at = text.find("<DataSet "); at != std::string::npos;
       at = text.find("<DataSet ", at + 1))
    out.emplace_back(quoted(text, "timestep", at), quoted(text, "file", at));
  return out;
}

/// The field data `material_names` of a series file (what its material numbers stand for).
std::vector<std::string> materialNames(vtkDataObject& data) {
  auto* names =
      vtkStringArray::SafeDownCast(data.GetFieldData()->GetAbstractArray("material_names"));
  REQUIRE(names != nullptr);
  std::vector<std::string> out;
  for (vtkIdType k = 0; k < names->GetNumberOfValues(); ++k) out.push_back(names->GetValue(k));
  return out;
}

bool hasTemporaryFiles(const fs::path& folder) {
  for (const auto& f : fs::directory_iterator(folder))
    if (f.path().extension() == ".tmp") return true;
  return false;
}

}  // namespace

TEST_CASE("SeriesWriter writes live tets with exact values and a .pvd", "[unit][output]") {
  TempFolder dir("full");
  Model m = twoBodies();
  const double times[3] = {0.0, 1e-5, 2.5e-5};
  {
    SeriesWriter w(dir.path / "out");  // the folder is created
    for (int s = 0; s < 3; ++s) {
      setStep(m, s);
      w.write(m, times[s]);
    }
    CHECK(w.outputCount() == 3);
  }

  const auto entries = pvdEntries(dir.path / "out" / "elements.pvd");
  REQUIRE(entries.size() == 3);
  CHECK(entries[0] == std::make_pair(std::string("0"), std::string("elements_000000.vtu")));
  CHECK(entries[1] == std::make_pair(std::string("1e-05"), std::string("elements_000001.vtu")));
  CHECK(entries[2] == std::make_pair(std::string("2.5e-05"), std::string("elements_000002.vtu")));
  CHECK_FALSE(hasTemporaryFiles(dir.path / "out"));

  const std::string raw = slurp(dir.path / "out" / "elements_000002.vtu");
  CHECK(raw.find("header_type=\"UInt64\"") != std::string::npos);
  CHECK(raw.find("compressor=\"vtkZLibDataCompressor\"") != std::string::npos);
  CHECK(raw.find("<AppendedData encoding=\"raw\">") != std::string::npos);

  for (int s = 0; s < 3; ++s) {
    setStep(m, s);  // the state the file was written from
    auto g = readVtu(dir.path / "out" / entries[s].second);
    REQUIRE(g->GetNumberOfCells() == 5);
    REQUIRE(g->GetNumberOfPoints() == 11);
    for (vtkIdType c = 0; c < 5; ++c) CHECK(g->GetCellType(c) == VTK_TETRA);

    vtkDataArray* tv = g->GetFieldData()->GetArray("TimeValue");
    REQUIRE(tv != nullptr);
    REQUIRE(tv->GetNumberOfTuples() == 1);
    CHECK(tv->GetComponent(0, 0) == times[s]);

    vtkCellData* cd = g->GetCellData();
    for (const auto& [name, comps] : std::vector<std::pair<const char*, int>>{
             {"stress", 6}, {"pressure", 1}, {"von_mises", 1}, {"plastic_strain", 1},
             {"plastic_strain_rate", 1}, {"temperature", 1}, {"damage", 1}, {"density", 1},
             {"body", 1}, {"material", 1}, {"element_id", 1}}) {
      INFO(name);
      REQUIRE(cd->GetArray(name) != nullptr);
      CHECK(cd->GetArray(name)->GetNumberOfComponents() == comps);
    }
    CHECK(cd->GetArray("body")->GetDataType() == VTK_INT);
    CHECK(cd->GetArray("material")->GetDataType() == VTK_INT);
    CHECK(cd->GetArray("element_id")->GetDataType() == VTK_TYPE_INT64);
    // what the material numbers stand for
    CHECK(materialNames(*g) == std::vector<std::string>{"steel core", "copper jacket"});
    // VTK and ParaView read a 6-component array as a symmetric tensor in the order XX YY ZZ
    // XY YZ XZ (vtkMath::TensorFromSymmetricTensor); the names must say the same
    const std::vector<std::string> tensor = {"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
    for (int k = 0; k < 6; ++k) {
      const char* component = cd->GetArray("stress")->GetComponentName(k);
      REQUIRE(component != nullptr);
      CHECK(std::string(component) == tensor[static_cast<std::size_t>(k)]);
    }

    vtkPointData* pd = g->GetPointData();
    REQUIRE(pd->GetArray("velocity") != nullptr);
    REQUIRE(pd->GetArray("displacement") != nullptr);
    REQUIRE(pd->GetArray("node_id") != nullptr);
    CHECK(pd->GetArray("velocity")->GetNumberOfComponents() == 3);
    CHECK(pd->GetArray("displacement")->GetNumberOfComponents() == 3);
    CHECK(pd->GetArray("node_id")->GetDataType() == VTK_TYPE_INT64);

    std::vector<long> elem_ids;
    for (vtkIdType c = 0; c < 5; ++c) {
      const auto e = static_cast<std::size_t>(cd->GetArray("element_id")->GetComponent(c, 0));
      elem_ids.push_back(static_cast<long>(e));
      const PointState& st = m.elems.state[e];
      CHECK(cd->GetArray("pressure")->GetComponent(c, 0) == st.p);
      CHECK(cd->GetArray("plastic_strain")->GetComponent(c, 0) == st.eps_p);
      CHECK(cd->GetArray("plastic_strain_rate")->GetComponent(c, 0) == st.eps_rate);
      CHECK(cd->GetArray("temperature")->GetComponent(c, 0) == st.T);
      CHECK(cd->GetArray("damage")->GetComponent(c, 0) == st.damage);
      CHECK(cd->GetArray("density")->GetComponent(c, 0) == m.elems.rho[e]);
      CHECK(cd->GetArray("von_mises")->GetComponent(c, 0) == vonMises(st.s));
      CHECK(cd->GetArray("body")->GetComponent(c, 0) == m.elems.body[e]);
      CHECK(cd->GetArray("material")->GetComponent(c, 0) == m.elems.material[e]);
      const double sigma[6] = {st.s.xx - st.p, st.s.yy - st.p, st.s.zz - st.p,
                               st.s.xy,        st.s.yz,        st.s.zx};
      for (int k = 0; k < 6; ++k) CHECK(cd->GetArray("stress")->GetComponent(c, k) == sigma[k]);
      // The cell's corners are the element's nodes.
      for (int k = 0; k < 4; ++k) {
        const vtkIdType p = g->GetCell(c)->GetPointId(k);
        CHECK(pd->GetArray("node_id")->GetComponent(p, 0) == m.elems.conn[e][k]);
      }
    }
    CHECK(elem_ids == std::vector<long>{1, 2, 3, 4, 5});

    std::vector<long> node_ids;
    for (vtkIdType p = 0; p < 11; ++p) {
      const auto n = static_cast<std::size_t>(pd->GetArray("node_id")->GetComponent(p, 0));
      node_ids.push_back(static_cast<long>(n));
      double x[3];
      g->GetPoint(p, x);
      const Vec3 u = m.nodes.x[n] - m.nodes.x0[n];
      for (int k = 0; k < 3; ++k) {
        CHECK(x[k] == m.nodes.x[n][k]);
        CHECK(pd->GetArray("velocity")->GetComponent(p, k) == m.nodes.v[n][k]);
        CHECK(pd->GetArray("displacement")->GetComponent(p, k) == u[k]);
      }
    }
    CHECK(node_ids == std::vector<long>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11});
  }
}

TEST_CASE("SeriesWriter writes every particle with exact values and a .pvd", "[unit][output]") {
  // Reference: the particles' own arrays, bit for bit (raw binary Float64 and Int64). Three
  // particles after a renumbering (ids 7, 3, 5), one tied to a face, one born a particle
  // (parent -1); "radius" is half the edge of the cube of the particle's volume, 0.5 cbrt(V)
  // (design.md, Output), what a glyph of the particle's own size needs.
  TempFolder dir("particles");
  Model m = twoBodies();
  setStep(m, 0);
  for (int k = 0; k < 3; ++k) {
    PointState st;
    st.eps_p = 0.3 + k / 7.0;
    st.damage = 0.1 * k + 1.0 / 9.0;
    st.p = -1e8 * (k + 1) / 3.0;
    st.T = 300.0 + k / 11.0;
    st.s = Sym{1e8 * (k + 1) / 7.0, -2e7 / (k + 2), 3e6, 4e7 / 3.0, -k * 1e6 / 9.0, 5e5};
    st.eps_rate = 1e4 * (k + 1) / 3.0;
    const double V = (1.0 + k / 3.0) * 1e-9;
    appendParticle(m.particles, Vec3(0.5 + k, 1.0 / (k + 3.0), -0.25 * k),
                   Vec3(100.0 / (k + 1), -7.0 * k, 1.0 / 3.0), 7.8e-6 * (1 + k / 5.0), V,
                   std::cbrt(V), 1.3e-3, st, k == 2 ? 1 : 0, k % 2, k == 1 ? -1 : 4 + k);
    m.particles.rho[k] = 7800.0 + k / 13.0;
  }
  m.particles.id = {7, 3, 5};
  m.particles.tie[1].face = {1, 2, 4};
  {
    SeriesOptions options;  // the scene's ids name the materials (the run's way)
    options.material_names = {"steel_4340", "OFHC_copper"};
    SeriesWriter w(dir.path, options);
    w.write(m, 0.0);
    m.particles.x[0].x() += 1.0 / 3.0;  // the second file holds the moved state
    w.write(m, 1.5e-6);
  }
  const auto entries = pvdEntries(dir.path / "particles.pvd");
  REQUIRE(entries.size() == 2);
  CHECK(entries[0] == std::make_pair(std::string("0"), std::string("particles_000000.vtp")));
  CHECK(entries[1] == std::make_pair(std::string("1.5e-06"), std::string("particles_000001.vtp")));
  CHECK_FALSE(hasTemporaryFiles(dir.path));

  auto reader = vtkSmartPointer<vtkXMLPolyDataReader>::New();
  reader->SetFileName((dir.path / "particles_000001.vtp").c_str());
  reader->Update();
  REQUIRE(reader->GetErrorCode() == 0);
  vtkPolyData* poly = reader->GetOutput();
  REQUIRE(poly->GetNumberOfPoints() == 3);
  REQUIRE(poly->GetNumberOfVerts() == 3);
  REQUIRE(poly->GetFieldData()->GetArray("TimeValue") != nullptr);
  CHECK(poly->GetFieldData()->GetArray("TimeValue")->GetComponent(0, 0) == 1.5e-6);
  vtkPointData* pd = poly->GetPointData();
  const auto value = [&](const char* name, vtkIdType i, int k = 0) {
    vtkDataArray* a = pd->GetArray(name);
    REQUIRE(a != nullptr);
    return a->GetComponent(i, k);
  };
  CHECK(pd->GetArray("body")->GetDataType() == VTK_INT);
  CHECK(pd->GetArray("parent_element")->GetDataType() == VTK_TYPE_INT64);
  CHECK(pd->GetArray("particle_id")->GetDataType() == VTK_TYPE_INT64);
  const Particles& pa = m.particles;
  for (vtkIdType i = 0; i < 3; ++i) {
    INFO("particle " << i);
    double x[3];
    poly->GetPoint(i, x);
    for (int k = 0; k < 3; ++k) {
      CHECK(x[k] == pa.x[i][k]);
      CHECK(value("velocity", i, k) == pa.v[i][k]);
    }
    CHECK(value("radius", i) == 0.5 * std::cbrt(pa.V[i]));
    CHECK(value("mass", i) == pa.m[i]);
    CHECK(value("density", i) == pa.rho[i]);
    CHECK(value("plastic_strain", i) == pa.state[i].eps_p);
    CHECK(value("damage", i) == pa.state[i].damage);
    CHECK(value("pressure", i) == pa.state[i].p);
    // the elements' fields all have theirs: a field drawn on both means the same
    CHECK(value("von_mises", i) == vonMises(pa.state[i].s));
    CHECK(value("plastic_strain_rate", i) == pa.state[i].eps_rate);
    CHECK(value("temperature", i) == pa.state[i].T);
    CHECK(value("tied", i) == (i == 1 ? 1.0 : 0.0));
    CHECK(value("body", i) == pa.body[i]);
    CHECK(value("material", i) == pa.material[i]);
    CHECK(value("parent_element", i) == pa.parent[i]);
    CHECK(value("particle_id", i) == pa.id[i]);
  }
  CHECK(value("parent_element", 1) == -1);
  CHECK(value("material", 1) == 1);
  CHECK(materialNames(*poly) == std::vector<std::string>{"steel_4340", "OFHC_copper"});
}

TEST_CASE("SeriesWriter writes only the requested fields", "[unit][output]") {
  TempFolder dir("fields");
  Model m = twoBodies();
  setStep(m, 1);
  SeriesOptions opt;
  opt.fields = {"pressure", "velocity"};
  SeriesWriter w(dir.path, opt);
  w.write(m, 0.5);
  auto g = readVtu(dir.path / "elements_000000.vtu");
  // the list's, and what fesph's images read (fesph render, the run's end): body, damage,
  // plastic_strain
  CHECK(g->GetCellData()->GetNumberOfArrays() == 4);
  CHECK(g->GetCellData()->GetArray("pressure") != nullptr);
  for (const char* view : {"body", "damage", "plastic_strain"}) {
    INFO(view);
    CHECK(g->GetCellData()->GetArray(view) != nullptr);
  }
  CHECK(g->GetPointData()->GetNumberOfArrays() == 1);
  CHECK(g->GetPointData()->GetArray("velocity") != nullptr);
  REQUIRE(g->GetFieldData()->GetArray("TimeValue") != nullptr);
  CHECK(g->GetFieldData()->GetArray("TimeValue")->GetComponent(0, 0) == 0.5);
}

TEST_CASE("SeriesWriter rejects unknown field names", "[unit][output]") {
  TempFolder dir("unknown");
  SeriesOptions opt;
  opt.fields = {"pressure", "presure"};
  try {
    SeriesWriter w(dir.path, opt);
    FAIL("no exception for an unknown field");
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    CHECK(what.find("presure") != std::string::npos);
    CHECK(what.find("von_mises") != std::string::npos);  // the allowed list
  }
  // Nothing was created in the folder by the failed construction.
  CHECK_FALSE(fs::exists(dir.path / "elements.pvd"));
}

TEST_CASE("SeriesWriter starts fresh or appends to an existing series", "[unit][output]") {
  TempFolder dir("restart");
  Model m = twoBodies();
  setStep(m, 0);
  {
    SeriesWriter w(dir.path);
    w.write(m, 0.0);
    w.write(m, 1.0);
    w.write(m, 2.0);
  }
  SECTION("append continues the numbering and keeps the old entries") {
    SeriesOptions opt;
    opt.append = true;
    SeriesWriter w(dir.path, opt);
    CHECK(w.outputCount() == 3);
    w.write(m, 3.0);
    const auto entries = pvdEntries(dir.path / "elements.pvd");
    REQUIRE(entries.size() == 4);
    CHECK(entries[0].second == "elements_000000.vtu");
    CHECK(entries[3] == std::make_pair(std::string("3"), std::string("elements_000003.vtu")));
    CHECK(fs::exists(dir.path / "elements_000003.vtu"));
  }
  SECTION("a fresh series replaces the old one and removes its files") {
    SeriesWriter w(dir.path);
    CHECK(w.outputCount() == 0);
    CHECK_FALSE(fs::exists(dir.path / "elements.pvd"));
    CHECK_FALSE(fs::exists(dir.path / "elements_000002.vtu"));
    w.write(m, 0.25);
    const auto entries = pvdEntries(dir.path / "elements.pvd");
    REQUIRE(entries.size() == 1);
    CHECK(entries[0] == std::make_pair(std::string("0.25"), std::string("elements_000000.vtu")));
  }
  CHECK_FALSE(hasTemporaryFiles(dir.path));
}

TEST_CASE("PvdCollection reads back what it wrote", "[unit][output]") {
  TempFolder dir("pvd");
  fs::create_directories(dir.path);
  const double times[3] = {0.0, 0.1 + 0.2, 1.0 / 3.0};
  {
    PvdCollection pvd(dir.path / "x.pvd", false);
    for (int i = 0; i < 3; ++i) pvd.add(times[i], "x_" + std::to_string(i) + ".vtu");
    // a name that leaves the folder, or is the folder: a fresh series deletes the files its
    // .pvd lists, so such an entry would take a folder with it
    for (const char* bad : {"../escape.vtu", "..", ".", "", "a/b.vtu", "a&b.vtu"})
      CHECK_THROWS_AS(pvd.add(4.0, bad), std::invalid_argument);
    CHECK(pvd.entries().size() == 3);
  }
  PvdCollection back(dir.path / "x.pvd", true);
  REQUIRE(back.entries().size() == 3);
  for (int i = 0; i < 3; ++i) {
    CHECK(back.entries()[i].time == times[i]);  // shortest round-trip form is exact
    CHECK(back.entries()[i].file == "x_" + std::to_string(i) + ".vtu");
  }
}

TEST_CASE("PvdCollection reads a .pvd written elsewhere, attributes by their whole names",
          "[unit][output]") {
  // Reference: the .pvd format (paraview.md): <DataSet timestep=".." part=".." file=".."/>,
  // attributes in any order, other attributes allowed. One whose name ends in "file" or
  // "timestep" (a tool's own "group", "xfile") must not be taken for them.
  TempFolder dir("pvd_foreign");
  fs::create_directories(dir.path);
  {
    std::ofstream out(dir.path / "y.pvd");
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n"
           "  <Collection>\n"
           "    <DataSet xtimestep=\"9\" sourcefile=\"wrong.vtu\" file=\"y_0.vtu\" "
           "timestep=\"2.5e-06\"/>\n"
           "    <DataSet part=\"0\" timestep=\"5e-06\" group=\"\" file=\"y_1.vtu\"/>\n"
           "  </Collection>\n</VTKFile>\n";
  }
  PvdCollection back(dir.path / "y.pvd", true);
  REQUIRE(back.entries().size() == 2);
  CHECK(back.entries()[0].time == 2.5e-6);
  CHECK(back.entries()[0].file == "y_0.vtu");
  CHECK(back.entries()[1].time == 5e-6);
  CHECK(back.entries()[1].file == "y_1.vtu");
}

TEST_CASE("a VTK failure's cause reads as words: its error code, or the errno it passes on",
          "[unit][output]") {
  // The XML writers pass the system's errno on as their error code (vtkXMLWriter): ENOSPC is
  // a full disk, which a run writing its series must say (not "VTK error 28").
  CHECK(fesph::vtkFailure(vtkErrorCode::NoError).empty());
  CHECK(fesph::vtkFailure(ENOSPC) == "the disk is full");
  CHECK(fesph::vtkFailure(vtkErrorCode::OutOfDiskSpaceError) == "the disk is full");
  CHECK(fesph::vtkFailure(EACCES) == "Permission denied");
  CHECK(fesph::vtkFailure(vtkErrorCode::PrematureEndOfFileError) ==
        "the file ends early (cut short?)");
  CHECK(fesph::cannotWrite("a.vtu", ENOSPC) == "cannot write a.vtu: the disk is full");
  // Without quietVtk no VTK message is kept: the code alone, or nothing more than the file.
  CHECK(fesph::cannotRead("b.vtu", vtkErrorCode::NoError) == "cannot read b.vtu");
}
