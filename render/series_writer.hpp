// SPDX-License-Identifier: MIT
// ParaView time series of the solver state: one .vtu per output step (live tetrahedra) listed
// in a .pvd collection. Every file is written under a temporary name and renamed into place.
#pragma once

#include "core/state/model.hpp"

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

class vtkDataObject;

namespace fesph {

/// A ParaView .pvd collection of (time, file) entries. The .pvd is rewritten after every
/// append through a temporary file and a rename, so it only ever lists complete files.
class PvdCollection {
 public:
  struct Entry {
    double time;
    std::string file;  ///< relative to the folder of the .pvd
  };

  /// `append`: read the entries of an existing `pvd_path` back (none if it does not exist).
  /// Otherwise start empty: an existing .pvd and the data files it lists are deleted.
  /// With `append`, entries after the first `keep` are dropped (a restart continues from its
  /// checkpoint; later files get overwritten as the run reaches them again).
  PvdCollection(std::filesystem::path pvd_path, bool append,
                std::size_t keep = static_cast<std::size_t>(-1));

  /// Record `file` (a plain file name in the .pvd's folder) at `time` and rewrite the .pvd.
  void add(double time, const std::string& file);

  const std::vector<Entry>& entries() const { return entries_; }
  const std::filesystem::path& path() const { return path_; }

 private:
  void save() const;

  std::filesystem::path path_;
  std::vector<Entry> entries_;
};

struct SeriesOptions {
  /// Cell and point arrays to write (names from SeriesWriter::elementFields()); empty: all.
  std::vector<std::string> fields;
  /// Continue the series found in the folder (restarts) instead of starting a fresh one.
  bool append = false;
  /// With `append`: keep only the first `keep` steps of the series found.
  std::size_t keep = static_cast<std::size_t>(-1);
  /// What the `material` arrays' numbers stand for (the scene's material ids, in the model's
  /// order), written as the field data `material_names`; empty: each Material::name.
  std::vector<std::string> material_names;
};

/// Writes elements_NNNNNN.vtu + elements.pvd and particles_NNNNNN.vtp + particles.pvd (one
/// vertex cell per particle; an empty but valid file while there are none) into one folder.
class SeriesWriter {
 public:
  /// Creates `folder` if missing. Throws std::invalid_argument for an unknown field name.
  explicit SeriesWriter(std::filesystem::path folder, SeriesOptions options = {});

  /// Write the live tetrahedra of `model` as output step `outputCount()` at `time` (s).
  void write(const Model& model, double time);

  /// Number of steps in the series so far (the index of the next file).
  std::size_t outputCount() const { return elements_.entries().size(); }
  /// Time of the last step in the series (s); -1 while it has none.
  double lastTime() const {
    return elements_.entries().empty() ? -1.0 : elements_.entries().back().time;
  }
  const std::filesystem::path& folder() const { return folder_; }

  /// Names accepted in SeriesOptions::fields for the element series.
  static const std::vector<std::string>& elementFields();

 private:
  bool wants(const std::string& field) const;
  void writeParticles(const Model& model, double time);

  void addMaterialNames(vtkDataObject& data, const Model& model) const;

  std::filesystem::path folder_;
  std::vector<std::string> fields_;
  std::vector<std::string> material_names_;
  PvdCollection elements_;
  PvdCollection particles_;
};

}  // namespace fesph
