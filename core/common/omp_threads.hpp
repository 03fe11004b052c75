// SPDX-License-Identifier: MIT
// The OpenMP thread queries the solver's per-thread buffers need, with their serial values when
// the code is built without OpenMP.
#pragma once

#ifdef _OPENMP
#include <omp.h>
#endif

namespace fesph {

/// Threads a parallel region started now would have (size per-thread buffers by it).
inline int maxThreads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

/// Threads of the team running the current parallel region (1 outside one).
inline int teamSize() {
#ifdef _OPENMP
  return omp_get_num_threads();
#else
  return 1;
#endif
}

/// This thread's number within its team (0 outside a parallel region).
inline int threadId() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

}  // namespace fesph
