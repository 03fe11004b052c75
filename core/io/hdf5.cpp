// SPDX-License-Identifier: MIT
#include "core/io/hdf5.hpp"

#include "core/common/error.hpp"

#include <filesystem>

namespace fesph::h5 {

namespace {

// The library prints its error stack to stderr by default; our errors say it in one line.
struct Quiet {
  Quiet() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }
};

void quiet() { static const Quiet once; }

hid_t check(hid_t id, const std::string& what) {
  if (id < 0) throw RunError("HDF5: cannot " + what);
  return id;
}

void check(herr_t status, const std::string& what) {
  if (status < 0) throw RunError("HDF5: cannot " + what);
}

std::string objectName(const Handle& loc) {
  char buf[512];
  const ssize_t n = H5Iget_name(loc.id(), buf, sizeof buf);
  return n > 0 ? std::string(buf) : std::string("?");
}

std::string fileName(const Handle& loc) {
  char buf[1024];
  const ssize_t n = H5Fget_name(loc.id(), buf, sizeof buf);
  return n > 0 ? std::string(buf) : std::string("?");
}

// "file.h5:/group/name" for messages.
std::string where(const Handle& loc, const std::string& name) {
  std::string path = objectName(loc);
  if (path.empty() || path.back() != '/') path += '/';
  return fileName(loc) + ":" + path + name;
}

Handle scalarSpace() { return Handle(check(H5Screate(H5S_SCALAR), "create a dataspace")); }

Handle writableAttribute(const Handle& loc, const std::string& name, hid_t type) {
  if (H5Aexists(loc.id(), name.c_str()) > 0) H5Adelete(loc.id(), name.c_str());
  const Handle space = scalarSpace();
  return Handle(check(H5Acreate2(loc.id(), name.c_str(), type, space.id(), H5P_DEFAULT,
                                 H5P_DEFAULT),
                      "create attribute " + where(loc, name)));
}

Handle openAttribute(const Handle& loc, const std::string& name) {
  if (H5Aexists(loc.id(), name.c_str()) <= 0)
    throw RunError(where(loc, name) + ": attribute missing");
  return Handle(check(H5Aopen(loc.id(), name.c_str(), H5P_DEFAULT),
                      "open attribute " + where(loc, name)));
}

}  // namespace

void Handle::close() {
  if (id_ < 0) return;
  switch (H5Iget_type(id_)) {
    case H5I_FILE: H5Fclose(id_); break;
    case H5I_GROUP: H5Gclose(id_); break;
    case H5I_DATASET: H5Dclose(id_); break;
    case H5I_DATASPACE: H5Sclose(id_); break;
    case H5I_DATATYPE: H5Tclose(id_); break;
    case H5I_ATTR: H5Aclose(id_); break;
    case H5I_GENPROP_LST: H5Pclose(id_); break;
    default: break;
  }
  id_ = H5I_INVALID_HID;
}

template <> hid_t nativeType<double>() { return H5T_NATIVE_DOUBLE; }
template <> hid_t nativeType<int>() { return H5T_NATIVE_INT; }
template <> hid_t nativeType<long>() { return H5T_NATIVE_LONG; }
template <> hid_t nativeType<unsigned long>() { return H5T_NATIVE_ULONG; }
template <> hid_t nativeType<std::uint8_t>() { return H5T_NATIVE_UINT8; }
template <> hid_t nativeType<std::uint32_t>() { return H5T_NATIVE_UINT32; }

Handle openFile(const std::string& path, Mode mode) {
  quiet();
  if (mode == Mode::Create) {
    return Handle(check(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                        "create " + path));
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw RunError(path + ": no such file");
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw RunError(path + ": not an HDF5 file (or its header is damaged)");
  const hid_t id =
      H5Fopen(path.c_str(), mode == Mode::Read ? H5F_ACC_RDONLY : H5F_ACC_RDWR, H5P_DEFAULT);
  if (id < 0) throw RunError(path + ": cannot open as HDF5 (truncated or damaged file)");
  return Handle(id);
}

void flush(const Handle& file) { check(H5Fflush(file.id(), H5F_SCOPE_GLOBAL), "flush"); }

Handle root(const Handle& file) {
  return Handle(check(H5Gopen2(file.id(), "/", H5P_DEFAULT), "open the root group"));
}

Handle createGroup(const Handle& loc, const std::string& name) {
  return Handle(check(H5Gcreate2(loc.id(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                      "create group " + where(loc, name)));
}

Handle openGroup(const Handle& loc, const std::string& name) {
  if (!exists(loc, name)) throw RunError(where(loc, name) + ": group missing");
  return Handle(check(H5Gopen2(loc.id(), name.c_str(), H5P_DEFAULT),
                      "open group " + where(loc, name)));
}

bool exists(const Handle& loc, const std::string& name) {
  return H5Lexists(loc.id(), name.c_str(), H5P_DEFAULT) > 0;
}

void writeAttribute(const Handle& loc, const std::string& name, const std::string& value) {
  const Handle type = stringType(value.size() + 1);
  const Handle attr = writableAttribute(loc, name, type.id());
  check(H5Awrite(attr.id(), type.id(), value.c_str()), "write attribute " + where(loc, name));
}

void writeAttribute(const Handle& loc, const std::string& name, double value) {
  const Handle attr = writableAttribute(loc, name, H5T_IEEE_F64LE);
  check(H5Awrite(attr.id(), H5T_NATIVE_DOUBLE, &value), "write attribute " + where(loc, name));
}

void writeAttribute(const Handle& loc, const std::string& name, std::int64_t value) {
  const Handle attr = writableAttribute(loc, name, H5T_STD_I64LE);
  check(H5Awrite(attr.id(), H5T_NATIVE_INT64, &value), "write attribute " + where(loc, name));
}

bool hasAttribute(const Handle& loc, const std::string& name) {
  return H5Aexists(loc.id(), name.c_str()) > 0;
}

std::string readStringAttribute(const Handle& loc, const std::string& name) {
  const Handle attr = openAttribute(loc, name);
  const Handle type(check(H5Aget_type(attr.id()), "read attribute " + where(loc, name)));
  if (H5Tget_class(type.id()) != H5T_STRING || H5Tis_variable_str(type.id()) > 0)
    throw RunError(where(loc, name) + ": not a fixed-length string");
  const std::size_t size = H5Tget_size(type.id());
  std::string value(size, '\0');
  const Handle mem = stringType(size);
  check(H5Aread(attr.id(), mem.id(), value.data()), "read attribute " + where(loc, name));
  value.resize(value.find('\0') == std::string::npos ? size : value.find('\0'));
  return value;
}

double readDoubleAttribute(const Handle& loc, const std::string& name) {
  const Handle attr = openAttribute(loc, name);
  double value = 0;
  check(H5Aread(attr.id(), H5T_NATIVE_DOUBLE, &value), "read attribute " + where(loc, name));
  return value;
}

std::int64_t readIntAttribute(const Handle& loc, const std::string& name) {
  const Handle attr = openAttribute(loc, name);
  std::int64_t value = 0;
  check(H5Aread(attr.id(), H5T_NATIVE_INT64, &value), "read attribute " + where(loc, name));
  return value;
}

void writeText(const Handle& loc, const std::string& name, const std::string& text) {
  const Handle type = stringType(text.size() + 1);
  const Handle space = scalarSpace();
  const Handle set(check(H5Dcreate2(loc.id(), name.c_str(), type.id(), space.id(), H5P_DEFAULT,
                                    H5P_DEFAULT, H5P_DEFAULT),
                         "create dataset " + where(loc, name)));
  check(H5Dwrite(set.id(), type.id(), H5S_ALL, H5S_ALL, H5P_DEFAULT, text.c_str()),
        "write dataset " + where(loc, name));
}

std::string readText(const Handle& loc, const std::string& name) {
  if (!exists(loc, name)) throw RunError(where(loc, name) + ": dataset missing");
  const Handle set(check(H5Dopen2(loc.id(), name.c_str(), H5P_DEFAULT),
                         "open dataset " + where(loc, name)));
  const Handle type(check(H5Dget_type(set.id()), "read dataset " + where(loc, name)));
  if (H5Tget_class(type.id()) != H5T_STRING || H5Tis_variable_str(type.id()) > 0)
    throw RunError(where(loc, name) + ": not a fixed-length string");
  const std::size_t size = H5Tget_size(type.id());
  std::string text(size, '\0');
  const Handle mem = stringType(size);
  check(H5Dread(set.id(), mem.id(), H5S_ALL, H5S_ALL, H5P_DEFAULT, text.data()),
        "read dataset " + where(loc, name) + " (truncated or damaged file?)");
  const std::size_t end = text.find('\0');
  if (end != std::string::npos) text.resize(end);
  return text;
}

void writeArray(const Handle& loc, const std::string& name, hid_t type, const void* data,
                std::size_t rows, std::size_t cols) {
  const hsize_t dims[2] = {rows, cols};
  const Handle space(check(H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr),
                           "create a dataspace"));
  const Handle set(check(H5Dcreate2(loc.id(), name.c_str(), type, space.id(), H5P_DEFAULT,
                                    H5P_DEFAULT, H5P_DEFAULT),
                         "create dataset " + where(loc, name)));
  if (rows * cols > 0)
    check(H5Dwrite(set.id(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
          "write dataset " + where(loc, name));
}

std::pair<std::size_t, std::size_t> arrayShape(const Handle& loc, const std::string& name) {
  if (!exists(loc, name)) throw RunError(where(loc, name) + ": dataset missing");
  const Handle set(check(H5Dopen2(loc.id(), name.c_str(), H5P_DEFAULT),
                         "open dataset " + where(loc, name)));
  const Handle space(check(H5Dget_space(set.id()), "read dataset " + where(loc, name)));
  const int rank = H5Sget_simple_extent_ndims(space.id());
  if (rank < 1 || rank > 2) throw RunError(where(loc, name) + ": not a 1D or 2D dataset");
  hsize_t dims[2] = {0, 1};
  H5Sget_simple_extent_dims(space.id(), dims, nullptr);
  return {dims[0], dims[1]};
}

void readArray(const Handle& loc, const std::string& name, hid_t type, void* data) {
  const Handle set(check(H5Dopen2(loc.id(), name.c_str(), H5P_DEFAULT),
                         "open dataset " + where(loc, name)));
  const Handle space(check(H5Dget_space(set.id()), "read dataset " + where(loc, name)));
  if (H5Sget_simple_extent_npoints(space.id()) == 0) return;
  check(H5Dread(set.id(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
        "read dataset " + where(loc, name) + " (truncated or damaged file?)");
}

Table Table::create(const Handle& loc, const std::string& name, hid_t type,
                    std::vector<hsize_t> row_shape, const std::string& units) {
  Table t;
  t.type_ = Handle(check(H5Tcopy(type), "copy a datatype"));
  t.row_shape_ = std::move(row_shape);
  std::vector<hsize_t> dims{0}, max{H5S_UNLIMITED}, chunk{256};
  for (hsize_t d : t.row_shape_) {
    dims.push_back(d);
    max.push_back(d);
    chunk.push_back(d);
  }
  const int rank = static_cast<int>(dims.size());
  const Handle space(check(H5Screate_simple(rank, dims.data(), max.data()),
                           "create a dataspace"));
  const Handle plist(check(H5Pcreate(H5P_DATASET_CREATE), "create a property list"));
  check(H5Pset_chunk(plist.id(), rank, chunk.data()), "set the chunk size");
  t.set_ = Handle(check(H5Dcreate2(loc.id(), name.c_str(), type, space.id(), H5P_DEFAULT,
                                   plist.id(), H5P_DEFAULT),
                        "create dataset " + where(loc, name)));
  if (!units.empty()) writeAttribute(t.set_, "units", units);
  return t;
}

Table Table::open(const Handle& loc, const std::string& name, hid_t type, std::size_t rows) {
  Table t;
  t.type_ = Handle(check(H5Tcopy(type), "copy a datatype"));
  if (!exists(loc, name)) throw RunError(where(loc, name) + ": dataset missing");
  t.set_ = Handle(check(H5Dopen2(loc.id(), name.c_str(), H5P_DEFAULT),
                        "open dataset " + where(loc, name)));
  const Handle space(check(H5Dget_space(t.set_.id()), "read dataset " + where(loc, name)));
  const int rank = H5Sget_simple_extent_ndims(space.id());
  if (rank < 1) throw RunError(where(loc, name) + ": not a table");
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.id(), dims.data(), nullptr);
  if (dims[0] < rows)
    throw RunError(where(loc, name) + ": " + std::to_string(dims[0]) + " rows, expected " +
                   std::to_string(rows));
  t.row_shape_.assign(dims.begin() + 1, dims.end());
  dims[0] = rows;
  check(H5Dset_extent(t.set_.id(), dims.data()), "shorten " + where(loc, name));
  t.rows_ = rows;
  return t;
}

void Table::append(const void* row) {
  std::vector<hsize_t> dims{rows_ + 1}, start{rows_}, count{1};
  for (hsize_t d : row_shape_) {
    dims.push_back(d);
    start.push_back(0);
    count.push_back(d);
  }
  check(H5Dset_extent(set_.id(), dims.data()), "extend a dataset");
  const Handle file_space(check(H5Dget_space(set_.id()), "extend a dataset"));
  check(H5Sselect_hyperslab(file_space.id(), H5S_SELECT_SET, start.data(), nullptr,
                            count.data(), nullptr),
        "select a row");
  const Handle mem_space(check(H5Screate_simple(static_cast<int>(count.size()), count.data(),
                                                nullptr),
                               "create a dataspace"));
  check(H5Dwrite(set_.id(), type_.id(), mem_space.id(), file_space.id(), H5P_DEFAULT, row),
        "append a row");
  ++rows_;
}

Handle stringType(std::size_t size) {
  Handle type(check(H5Tcopy(H5T_C_S1), "copy a datatype"));
  check(H5Tset_size(type.id(), size < 1 ? 1 : size), "size a string type");
  check(H5Tset_strpad(type.id(), H5T_STR_NULLTERM), "pad a string type");
  return type;
}

}  // namespace fesph::h5
