// SPDX-License-Identifier: MIT
// What every HDF5 file of a run says about where it came from: fesph version, git commit of
// the build, HDF5 version and the unit system.
#pragma once

#include "core/io/hdf5.hpp"

#include <string>

namespace fesph {

/// Git commit the build was configured from ("unknown" outside a git checkout).
std::string gitHash();

/// Attributes fesph_version, git_hash, hdf5_version and units on `loc`.
void writeRunMetadata(const h5::Handle& loc);

}  // namespace fesph
