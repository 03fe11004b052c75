// SPDX-License-Identifier: MIT
#include "core/io/run_metadata.hpp"

namespace fesph {

void writeRunMetadata(const h5::Handle& loc) {
  h5::writeAttribute(loc, "fesph_version", std::string(FESPH_VERSION));
  h5::writeAttribute(loc, "git_hash", gitHash());
  h5::writeAttribute(loc, "hdf5_version", std::string(H5_VERS_INFO));
  h5::writeAttribute(loc, "units", std::string("SI: m, s, kg, N, Pa, J, K, m/s, kg m/s"));
}

}  // namespace fesph
