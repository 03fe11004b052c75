// SPDX-License-Identifier: MIT
// Writing a tet mesh as a Gmsh 2.2 ASCII file whose tets are in physical volumes, for the tests
// of bodies made of several volumes (one material each).
#pragma once

#include "core/mesh/mesh.hpp"

#include <filesystem>
#include <fstream>
#include <map>
#include <string>

namespace fesph::testing {

/// `mesh` as a 2.2 .msh at `path` (coordinates as they are: scale them in the scene), tet t in
/// the physical volume physical(centroid of t); `names`: tag -> name for $PhysicalNames.
template <class Physical>
void writeMshVolumes(const std::filesystem::path& path, const TetMesh& mesh,
                     const std::map<int, std::string>& names, Physical physical) {
  std::ofstream msh(path);
  msh << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n" << names.size() << "\n";
  for (const auto& [tag, name] : names) msh << "3 " << tag << " \"" << name << "\"\n";
  msh << "$EndPhysicalNames\n$Nodes\n" << mesh.nodes.size() << "\n";
  msh.precision(17);
  for (std::size_t a = 0; a < mesh.nodes.size(); ++a)
    msh << a + 1 << " " << mesh.nodes[a].x() << " " << mesh.nodes[a].y() << " "
        << mesh.nodes[a].z() << "\n";
  msh << "$EndNodes\n$Elements\n" << mesh.tets.size() << "\n";
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& c = mesh.tets[t];
    const Vec3 centre =
        0.25 * (mesh.nodes[c[0]] + mesh.nodes[c[1]] + mesh.nodes[c[2]] + mesh.nodes[c[3]]);
    msh << t + 1 << " 4 2 " << physical(centre) << " 1 " << c[0] + 1 << " " << c[1] + 1 << " "
        << c[2] + 1 << " " << c[3] + 1 << "\n";
  }
  msh << "$EndElements\n";
}

}  // namespace fesph::testing
