// SPDX-License-Identifier: MIT
#include "render/debris_table.hpp"

#include "core/common/error.hpp"

#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>

namespace fesph {

std::vector<DebrisParticle> readDebris(const std::string& run_dir, double time,
                                       const std::vector<vtkIdType>& plate_particles) {
  const vtkSmartPointer<vtkPolyData> pd = render_detail::readParticles(run_dir, time);
  std::vector<DebrisParticle> debris;
  if (!pd) return debris;
  std::vector<char> plate(static_cast<std::size_t>(pd->GetNumberOfPoints()), 0);
  for (vtkIdType i : plate_particles)
    if (i >= 0 && i < pd->GetNumberOfPoints()) plate[static_cast<std::size_t>(i)] = 1;
  vtkPointData* data = pd->GetPointData();
  const auto array = [&](const char* name, int components) {
    vtkDataArray* a = data->GetArray(name);
    if (!a || a->GetNumberOfComponents() != components)
      throw RunError(run_dir + ": the particle series has no " + std::to_string(components) +
                     "-component array \"" + name + "\"");
    return a;
  };
  vtkDataArray* velocity = array("velocity", 3);
  vtkDataArray* mass = array("mass", 1);
  vtkDataArray* radius = array("radius", 1);
  vtkDataArray* damage = array("damage", 1);
  vtkDataArray* body = array("body", 1);
  vtkDataArray* tied = array("tied", 1);
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i) {
    if (tied->GetTuple1(i) != 0) continue;  // held by an element face: still part of a plate
    if (plate[static_cast<std::size_t>(i)]) continue;  // a plate made of particles, in place
    DebrisParticle q;
    pd->GetPoint(i, q.x.data());
    velocity->GetTuple(i, q.v.data());
    q.mass = mass->GetTuple1(i);
    q.radius = radius->GetTuple1(i);
    q.damage = damage->GetTuple1(i);
    q.body = static_cast<int>(body->GetTuple1(i));
    debris.push_back(q);
  }
  return debris;
}

std::vector<TargetPlate> targetPlates(const std::vector<PlateImages>& images) {
  std::vector<TargetPlate> plates;
  for (const PlateImages& p : images) {
    const PlateHoles& h = p.holes;  // its frame and the plate proper's extent
    TargetPlate t;
    t.name = p.plate;
    t.body = p.body;
    t.centre = h.extentCentre();
    t.normal = h.normal;
    t.u = h.u;
    t.v = h.v;
    t.front = h.front - (t.centre - h.origin).dot(h.normal);  // u, v lie in the plane: ~front
    t.half_u = h.halfU();
    t.half_v = h.halfV();
    plates.push_back(t);
  }
  return plates;
}

DebrisSummary writeDebrisTable(const std::string& run_dir, double time,
                               const std::vector<PlateImages>& images, const std::string& out_dir) {
  const RunInfo info = readRunInfo(run_dir);
  DebrisOptions options;
  options.half = info.half;
  std::vector<vtkIdType> plate_particles;
  for (const PlateImages& p : images)
    plate_particles.insert(plate_particles.end(), p.particles.begin(), p.particles.end());
  const std::vector<Clump> clumps =
      findClumps(readDebris(run_dir, time, plate_particles), options);
  const std::vector<TargetPlate> plates = targetPlates(images);
  std::vector<std::string> names;
  for (const RunBody& b : info.bodies) names.push_back(b.name);
  return writeDebrisCsv(out_dir + "/debris.csv", time, clumps, plates, names);
}

}  // namespace fesph
