// SPDX-License-Identifier: MIT
// A thin RAII layer over the HDF5 C API: handles that close themselves, errors as RunError
// (the library's own error stack printing is switched off), and the few operations the
// history and checkpoint files need: 2D arrays of numbers, string and number attributes,
// and extendible chunked datasets that grow one row at a time.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace fesph::h5 {

/// Owns one HDF5 identifier (file, group, dataset, dataspace, datatype, attribute, plist).
class Handle {
 public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, H5I_INVALID_HID)) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      close();
      id_ = std::exchange(o.id_, H5I_INVALID_HID);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { close(); }
  hid_t id() const { return id_; }
  bool valid() const { return id_ >= 0; }
  void close();

 private:
  hid_t id_ = H5I_INVALID_HID;
};

/// The HDF5 memory type of a C++ number type.
template <class T> hid_t nativeType();

enum class Mode { Create, Read, ReadWrite };

/// Open or create `path`. Create truncates an existing file. Throws RunError naming the path
/// (a missing file, or one that is not HDF5 / truncated, is told apart).
Handle openFile(const std::string& path, Mode mode);
/// Flush the file's buffers to disk, so that it is valid if the process dies later.
void flush(const Handle& file);

/// The root group of a file.
Handle root(const Handle& file);
Handle createGroup(const Handle& loc, const std::string& name);
Handle openGroup(const Handle& loc, const std::string& name);
bool exists(const Handle& loc, const std::string& name);

// ---- attributes -----------------------------------------------------------------------
void writeAttribute(const Handle& loc, const std::string& name, const std::string& value);
void writeAttribute(const Handle& loc, const std::string& name, double value);
void writeAttribute(const Handle& loc, const std::string& name, std::int64_t value);
bool hasAttribute(const Handle& loc, const std::string& name);
std::string readStringAttribute(const Handle& loc, const std::string& name);
double readDoubleAttribute(const Handle& loc, const std::string& name);
std::int64_t readIntAttribute(const Handle& loc, const std::string& name);

// ---- text of any length, as a scalar string dataset (attributes are limited to 64 KiB) ----
void writeText(const Handle& loc, const std::string& name, const std::string& text);
std::string readText(const Handle& loc, const std::string& name);

// ---- fixed datasets: rows x cols numbers (cols = 1: a 1D dataset) -------------------------
void writeArray(const Handle& loc, const std::string& name, hid_t type, const void* data,
                std::size_t rows, std::size_t cols);
/// Rows and columns of a 1D or 2D dataset (a 1D one has cols = 1).
std::pair<std::size_t, std::size_t> arrayShape(const Handle& loc, const std::string& name);
/// Read the whole dataset into `data` (rows x cols elements of `type`).
void readArray(const Handle& loc, const std::string& name, hid_t type, void* data);

// ---- extendible datasets: one row appended at a time ----------------------------------------
/// A chunked dataset of `row_shape` elements per row (empty: scalars) that grows along its
/// first dimension.
class Table {
 public:
  Table() = default;
  /// Create `name` in `loc` with zero rows.
  static Table create(const Handle& loc, const std::string& name, hid_t type,
                      std::vector<hsize_t> row_shape, const std::string& units);
  /// Open an existing one and cut it to its first `rows` rows.
  static Table open(const Handle& loc, const std::string& name, hid_t type, std::size_t rows);
  /// Append one row of `type` elements (as many as the row shape holds).
  void append(const void* row);
  std::size_t rows() const { return rows_; }

 private:
  Handle set_;
  Handle type_;  ///< a copy of the element type
  std::vector<hsize_t> row_shape_;
  std::size_t rows_ = 0;
};

/// A fixed-length string type of `size` bytes (null-padded), for string tables.
Handle stringType(std::size_t size);

}  // namespace fesph::h5
