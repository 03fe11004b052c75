// SPDX-License-Identifier: MIT
// Reader for Gmsh ASCII .msh files, formats 2.2 and 4.1: keeps the linear tets (type 4) and
// the nodes they use, skips surface, line and point elements, and refuses any other volume
// element (hexahedra, prisms, pyramids, higher-order tets), which would otherwise leave a hole
// in the body. Every problem is reported as an InputError at its 1-based line.
#include "core/common/error.hpp"
#include "core/mesh/mesh.hpp"
#include "core/mesh/tet_assembly.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <string_view>
#include <unordered_map>

namespace fesph {
namespace {

constexpr long long kLinearTet = 4;  // Gmsh element type

/// The volume elements of Gmsh's element types other than the linear tet (GmshDefines.h, up
/// to the fourth-order tet), by name; "" for a type that is not one of them.
std::string volumeElementName(long long type) {
  switch (type) {
    case 5: return "8-node hexahedron";
    case 6: return "6-node prism";
    case 7: return "5-node pyramid";
    case 11: return "10-node tetrahedron";
    case 12: return "27-node hexahedron";
    case 13: return "18-node prism";
    case 14: return "14-node pyramid";
    case 17: return "20-node hexahedron";
    case 18: return "15-node prism";
    case 19: return "13-node pyramid";
    case 29: return "20-node tetrahedron";
    case 30: return "35-node tetrahedron";
    default: return "";
  }
}

/// The file as a sequence of non-blank lines split into tokens, with the current line number.
class MshLines {
 public:
  explicit MshLines(const std::string& path) : path_(path), in_(path) {
    if (!in_) throw InputError(path, 0, 0, "cannot open");
  }

  /// Moves to the next non-blank line; false at the end of the file.
  bool advance() {
    while (std::getline(in_, text_)) {
      ++line_;
      split();
      if (!tokens_.empty()) return true;
    }
    return false;
  }
  /// Moves to the next non-blank line, which must exist and hold at least `min_tokens`.
  void next(std::size_t min_tokens, const std::string& expected) {
    if (!advance()) fail("premature end of file: expected " + expected);
    if (tokens_.size() < min_tokens) fail("expected " + expected);
  }
  /// Moves to the next line, which must start with `keyword`.
  void expectKeyword(const std::string& keyword) {
    next(1, keyword);
    if (tokens_[0] != keyword) fail("expected " + keyword + ", found " + quoted(0));
  }

  std::size_t size() const { return tokens_.size(); }
  std::string token(std::size_t i) const { return std::string(tokens_[i]); }
  /// Token i quoted for a message, cut short: a binary file can hold very long "tokens".
  std::string quoted(std::size_t i) const {
    const std::string_view t = tokens_[i];
    return "'" + std::string(t.substr(0, 40)) + (t.size() > 40 ? "...'" : "'");
  }
  int line() const { return line_; }
  const std::string& text() const { return text_; }

  long long integer(std::size_t i, const char* what) const {
    const std::string_view t = tokens_[i];
    long long v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || end != t.data() + t.size())
      fail(std::string("expected ") + what + " (an integer), found " + quoted(i));
    return v;
  }
  long long count(std::size_t i, const char* what) const {
    const long long n = integer(i, what);
    if (n < 0) fail(std::string("expected ") + what + " >= 0, found " + quoted(i));
    return n;
  }
  double real(std::size_t i, const char* what) const {
    std::string_view t = tokens_[i];
    if (!t.empty() && t[0] == '+') t.remove_prefix(1);  // from_chars rejects a leading '+'
    double v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v))
      fail(std::string("expected ") + what + " (a finite number), found " + quoted(i));
    return v;
  }

  [[noreturn]] void fail(const std::string& what) const { throw InputError(path_, line_, 0, what); }

 private:
  void split() {
    tokens_.clear();
    const std::string_view s(text_);
    std::size_t i = 0;
    while (true) {
      i = s.find_first_not_of(" \t\r", i);
      if (i == std::string_view::npos) return;
      const std::size_t j = std::min(s.find_first_of(" \t\r", i), s.size());
      tokens_.push_back(s.substr(i, j - i));
      i = j;
    }
  }

  std::string path_;
  std::ifstream in_;
  std::string text_;
  std::vector<std::string_view> tokens_;  // views into text_
  int line_ = 0;
};

struct RawTet {
  long long tag;
  std::array<long long, 4> nodes;
  int line;
  long long group;  ///< 2.2: its physical tag (0: none); 4.1: its volume entity's tag
};

/// What the sections hold, before node tags are resolved.
struct RawMesh {
  std::vector<Vec3> nodes;
  std::unordered_map<long long, int> node_index;  // node tag -> position in `nodes`
  std::vector<RawTet> tets;
  int elements_line = 0;  // line of the $Elements header, for "no tetrahedra"
  bool groups_are_entities = false;  // 4.1: RawTet::group is an entity (its physicals below)
  std::map<long long, std::vector<long long>> volume_physicals;  // 4.1 volume entity -> tags
  std::map<long long, std::string> volume_names;  // physical tag -> name (dimension 3)
};

enum class MshVersion { V2, V41 };

MshVersion readHeader(MshLines& in) {
  in.expectKeyword("$MeshFormat");
  in.next(3, "version, file type and data size");
  const double version = in.real(0, "the format version");
  const bool binary = in.integer(1, "the file type") != 0;
  if (!(version >= 2.0 && version < 3.0) && version != 4.1)
    in.fail("unsupported .msh version " + in.quoted(0) + ": expected 2.2 or 4.1");
  if (binary) in.fail("binary .msh not supported: save as ASCII");
  in.expectKeyword("$EndMeshFormat");
  return version < 3.0 ? MshVersion::V2 : MshVersion::V41;
}

void addNode(MshLines& in, RawMesh& mesh, long long tag, const Vec3& x) {
  if (!mesh.node_index.emplace(tag, static_cast<int>(mesh.nodes.size())).second)
    in.fail("node " + std::to_string(tag) + " defined twice");
  mesh.nodes.push_back(x);
}

Vec3 readPoint(const MshLines& in, std::size_t first, double scale) {
  return scale * Vec3(in.real(first, "x"), in.real(first + 1, "y"), in.real(first + 2, "z"));
}

/// 2.2: a count, then "tag x y z" per line.
void readNodesV2(MshLines& in, RawMesh& mesh, double scale) {
  in.next(1, "the number of nodes");
  const long long n = in.count(0, "the number of nodes");
  for (long long i = 0; i < n; ++i) {
    in.next(4, "a node: tag x y z");
    addNode(in, mesh, in.integer(0, "a node tag"), readPoint(in, 1, scale));
  }
}

/// 4.1: blocks of "dim entity parametric count", then the block's tags, then its coordinates
/// (x y z, followed by `dim` parametric coordinates when `parametric` is 1).
void readNodesV41(MshLines& in, RawMesh& mesh, double scale) {
  in.next(4, "numEntityBlocks numNodes minNodeTag maxNodeTag");
  const long long blocks = in.count(0, "the number of node blocks");
  for (long long b = 0; b < blocks; ++b) {
    in.next(4, "a node block header: entityDim entityTag parametric numNodesInBlock");
    const long long dim = in.integer(0, "the entity dimension");
    if (dim < 0 || dim > 3) in.fail("expected an entity dimension 0 to 3, found " + in.quoted(0));
    const std::size_t min_tokens = 3 + (in.integer(2, "the parametric flag") != 0 ? dim : 0);
    const long long n = in.count(3, "the number of nodes in the block");
    std::vector<long long> tags;  // grown line by line: a bad count fails at the end of file
    for (long long i = 0; i < n; ++i) {
      in.next(1, "a node tag");
      tags.push_back(in.integer(0, "a node tag"));
    }
    for (long long tag : tags) {
      in.next(min_tokens, "node coordinates");
      addNode(in, mesh, tag, readPoint(in, 0, scale));
    }
  }
}

/// Keeps a tet of `group` whose node tags start at token `first` of the current line.
void addTet(MshLines& in, RawMesh& mesh, long long tag, std::size_t first, long long group) {
  if (in.size() != first + 4)
    in.fail("expected 4 node tags for tetrahedron " + std::to_string(tag));
  RawTet t{tag, {}, in.line(), group};
  for (int k = 0; k < 4; ++k) t.nodes[k] = in.integer(first + k, "a node tag");
  mesh.tets.push_back(t);
}

/// Refuses element `tag` of Gmsh type `type`, a volume element that is no linear tet.
[[noreturn]] void otherVolumeElement(const MshLines& in, long long tag, long long type) {
  const std::string name = volumeElementName(type);
  in.fail("element " + std::to_string(tag) + " is " +
          (name.empty() ? "a volume element" : "a " + name) + " (Gmsh type " +
          std::to_string(type) +
          "): fesph reads 4-node tetrahedra only; mesh the whole volume with them (in Gmsh "
          "no recombination, Mesh.ElementOrder = 1)");
}

/// 2.2: a count, then "tag type numTags tags... nodes..." per line.
void readElementsV2(MshLines& in, RawMesh& mesh) {
  in.next(1, "the number of elements");
  const long long n = in.count(0, "the number of elements");
  for (long long i = 0; i < n; ++i) {
    in.next(3, "an element: tag type numTags tags... nodes...");
    const long long tag = in.integer(0, "an element tag");
    const long long num_tags = in.count(2, "the number of element tags");
    const long long type = in.integer(1, "an element type");
    // the first tag is the physical group (Gmsh writes 0 for none)
    const long long physical =
        num_tags > 0 && in.size() > 3 ? in.integer(3, "a physical tag") : 0;
    if (type == kLinearTet) addTet(in, mesh, tag, 3 + num_tags, physical);
    else if (!volumeElementName(type).empty()) otherVolumeElement(in, tag, type);
  }
}

/// 4.1: blocks of "dim entity type count", then "tag nodes..." per line.
void readElementsV41(MshLines& in, RawMesh& mesh) {
  in.next(4, "numEntityBlocks numElements minElementTag maxElementTag");
  const long long blocks = in.count(0, "the number of element blocks");
  for (long long b = 0; b < blocks; ++b) {
    in.next(4, "an element block header: entityDim entityTag elementType numElementsInBlock");
    // A block of a volume entity holds volume elements whatever their type.
    const bool volume = in.integer(0, "an entity dimension") == 3;
    const long long entity = in.integer(1, "an entity tag");
    const long long type = in.integer(2, "an element type");
    const bool tets = type == kLinearTet;
    const bool other = !tets && (volume || !volumeElementName(type).empty());
    const long long n = in.count(3, "the number of elements in the block");
    for (long long i = 0; i < n; ++i) {
      in.next(2, "an element: tag nodes...");
      const long long tag = in.integer(0, "an element tag");
      if (tets) addTet(in, mesh, tag, 1, entity);
      else if (other) otherVolumeElement(in, tag, type);
    }
  }
}

/// $PhysicalNames: "dimension tag \"name\"" per line; the volumes' names are kept.
void readPhysicalNames(MshLines& in, RawMesh& mesh) {
  in.next(1, "the number of physical names");
  const long long n = in.count(0, "the number of physical names");
  for (long long i = 0; i < n; ++i) {
    in.next(3, "a physical name: dimension tag \"name\"");
    const std::string& text = in.text();
    const std::size_t open = text.find('"'), close = text.rfind('"');
    if (open == std::string::npos || close == open)
      in.fail("expected a physical name in double quotes");
    if (in.integer(0, "a dimension") == 3)
      mesh.volume_names[in.integer(1, "a physical tag")] = text.substr(open + 1, close - open - 1);
  }
}

/// 4.1 $Entities: the physical tags of each volume ("tag minX minY minZ maxX maxY maxZ
/// numPhysicalTags tags... numBoundingSurfaces tags..."); points, curves, surfaces skipped.
void readEntitiesV41(MshLines& in, RawMesh& mesh) {
  in.next(4, "numPoints numCurves numSurfaces numVolumes");
  const long long skip = in.count(0, "the number of points") +
                         in.count(1, "the number of curves") +
                         in.count(2, "the number of surfaces");
  const long long volumes = in.count(3, "the number of volumes");
  for (long long i = 0; i < skip; ++i) in.next(1, "an entity");
  for (long long i = 0; i < volumes; ++i) {
    in.next(8, "a volume: tag minX minY minZ maxX maxY maxZ numPhysicalTags tags...");
    const long long n = in.count(7, "the number of physical tags");
    if (in.size() < static_cast<std::size_t>(8 + n))
      in.fail("expected " + std::to_string(n) + " physical tags");
    std::vector<long long>& tags = mesh.volume_physicals[in.integer(0, "a volume tag")];
    for (long long k = 0; k < n; ++k) tags.push_back(in.integer(8 + k, "a physical tag"));
  }
}

/// Skips a section the tets do not need ($Periodic, $NodeData, $PartitionedEntities...).
void skipSection(MshLines& in, const std::string& end) {
  do {
    if (!in.advance()) in.fail("premature end of file: expected " + end);
  } while (in.token(0) != end);
}

RawMesh readSections(MshLines& in, double scale) {
  const MshVersion version = readHeader(in);
  RawMesh mesh;
  mesh.groups_are_entities = version == MshVersion::V41;
  while (in.advance()) {
    const std::string section = in.token(0);
    if (section[0] != '$')
      in.fail("expected a section header such as $Nodes, found " + in.quoted(0));
    const std::string end = "$End" + section.substr(1);
    if (section == "$Nodes") {
      version == MshVersion::V2 ? readNodesV2(in, mesh, scale) : readNodesV41(in, mesh, scale);
      in.expectKeyword(end);
    } else if (section == "$Elements") {
      mesh.elements_line = in.line();
      version == MshVersion::V2 ? readElementsV2(in, mesh) : readElementsV41(in, mesh);
      in.expectKeyword(end);
    } else if (section == "$PhysicalNames") {
      readPhysicalNames(in, mesh);
      in.expectKeyword(end);
    } else if (section == "$Entities" && version == MshVersion::V41) {
      readEntitiesV41(in, mesh);
      in.expectKeyword(end);
    } else {
      skipSection(in, end);
    }
  }
  return mesh;
}

/// Resolves node tags to positions and rejects dangling and zero-volume tets at their line.
std::vector<std::array<int, 4>> resolveTets(const std::string& path, const RawMesh& raw) {
  std::vector<std::array<int, 4>> tets(raw.tets.size());
  for (std::size_t e = 0; e < tets.size(); ++e) {
    const RawTet& t = raw.tets[e];
    for (int k = 0; k < 4; ++k) {
      const auto it = raw.node_index.find(t.nodes[k]);
      if (it == raw.node_index.end())
        throw InputError(path, t.line, 0, "element " + std::to_string(t.tag) +
                                              " references undefined node " +
                                              std::to_string(t.nodes[k]));
      tets[e][k] = it->second;
    }
    const auto& x = raw.nodes;
    if (mesh_detail::isFlatTet(x[tets[e][0]], x[tets[e][1]], x[tets[e][2]], x[tets[e][3]]))
      throw InputError(path, t.line, 0,
                       "element " + std::to_string(t.tag) + " is a zero-volume tetrahedron");
  }
  return tets;
}

/// The physical volumes the tets belong to, as "1 \"core\", 2 \"jacket\"" (a tag without a
/// name alone); "none" when no tet has one.
std::string physicalVolumes(const RawMesh& raw) {
  std::set<long long> tags;
  for (const RawTet& t : raw.tets) {
    if (!raw.groups_are_entities) {
      if (t.group != 0) tags.insert(t.group);
    } else if (const auto it = raw.volume_physicals.find(t.group);
               it != raw.volume_physicals.end()) {
      tags.insert(it->second.begin(), it->second.end());
    }
  }
  std::string list;
  for (long long tag : tags) {
    list += (list.empty() ? "" : ", ") + std::to_string(tag);
    if (const auto it = raw.volume_names.find(tag); it != raw.volume_names.end())
      list += " \"" + it->second + "\"";
  }
  return list.empty() ? "none" : list;
}

/// The physical tag `volume` asks for: its name's, or its own; 0 (no volume's) for a name no
/// volume has, which untagged 2.2 tets (group 0) must not match either.
long long volumeTag(const RawMesh& raw, const MshVolume& volume) {
  if (volume.name.empty()) return volume.tag;
  for (const auto& [tag, name] : raw.volume_names)
    if (name == volume.name) return tag;
  return 0;
}

bool inVolume(const RawMesh& raw, const RawTet& t, long long tag) {
  if (tag == 0) return false;
  if (!raw.groups_are_entities) return t.group == tag;
  const auto it = raw.volume_physicals.find(t.group);
  return it != raw.volume_physicals.end() &&
         std::find(it->second.begin(), it->second.end(), tag) != it->second.end();
}

std::string volumeText(const MshVolume& v) {
  return v.name.empty() ? std::to_string(v.tag) : "\"" + v.name + "\"";
}

/// Keeps the tets of the physical volumes asked for; returns each kept tet's volume (its
/// index in `volumes`). `whole`: every tet must be in one of them (a body of several
/// materials leaves none of its file out). The scene asked for the volumes, so the errors
/// carry no line of the file.
std::vector<int> selectVolumes(const std::string& path, RawMesh& raw,
                               const std::vector<MshVolume>& volumes, bool whole) {
  std::vector<long long> tags;
  for (const MshVolume& v : volumes) tags.push_back(volumeTag(raw, v));
  const std::string list = physicalVolumes(raw);
  std::vector<RawTet> kept;
  std::vector<int> region;
  std::vector<std::size_t> count(volumes.size(), 0);
  std::size_t outside = 0;
  const RawTet* first_outside = nullptr;
  for (const RawTet& t : raw.tets) {
    int in = -1;
    for (std::size_t k = 0; k < tags.size(); ++k) {
      if (!inVolume(raw, t, tags[k])) continue;
      if (in >= 0)
        throw InputError(path, 0, 0,
                         "element " + std::to_string(t.tag) + " (line " +
                             std::to_string(t.line) + ") is in both physical volumes " +
                             volumeText(volumes[static_cast<std::size_t>(in)]) + " and " +
                             volumeText(volumes[k]) + ": give each tet one material");
      in = static_cast<int>(k);
    }
    if (in < 0) {
      if (outside++ == 0) first_outside = &t;
      continue;
    }
    ++count[static_cast<std::size_t>(in)];
    kept.push_back(t);
    region.push_back(in);
  }
  for (std::size_t k = 0; k < volumes.size(); ++k)
    if (count[k] == 0)
      throw InputError(path, 0, 0,
                       "no tetrahedra in the physical volume " + volumeText(volumes[k]) +
                           "; the mesh's physical volumes: " + list);
  if (whole && outside > 0)
    throw InputError(path, 0, 0,
                     std::to_string(outside) + " of the mesh's " +
                         std::to_string(raw.tets.size()) +
                         " tetrahedra are in none of the physical volumes given a material "
                         "(the first: element " + std::to_string(first_outside->tag) +
                         ", line " + std::to_string(first_outside->line) +
                         "); the mesh's physical volumes: " + list);
  raw.tets = std::move(kept);
  return region;
}

RawMesh readTets(const std::string& path, double scale) {
  if (!(scale > 0 && std::isfinite(scale)))
    throw InputError(path, 0, 0, "mesh scale must be a positive number");
  MshLines in(path);
  RawMesh raw = readSections(in, scale);
  if (raw.tets.empty())
    throw InputError(path, raw.elements_line > 0 ? raw.elements_line : in.line(), 0,
                     "no linear tetrahedra (element type 4) in the mesh");
  return raw;
}

}  // namespace

TetMesh readMsh(const std::string& path, double scale, const MshVolume& volume) {
  RawMesh raw = readTets(path, scale);
  if (!volume.all()) selectVolumes(path, raw, {volume}, false);
  return mesh_detail::assembleTetMesh(raw.nodes, resolveTets(path, raw));
}

TetMesh readMsh(const std::string& path, double scale, const std::vector<MshVolume>& volumes) {
  RawMesh raw = readTets(path, scale);
  std::vector<int> region = selectVolumes(path, raw, volumes, true);
  TetMesh mesh = mesh_detail::assembleTetMesh(raw.nodes, resolveTets(path, raw));
  mesh.region = std::move(region);
  return mesh;
}

}  // namespace fesph
