// SPDX-License-Identifier: MIT
// Per-thread buffers that do not share cache lines.
#pragma once

namespace fesph {

/// One thread's buffer, alone on its cache lines. A vector's header (begin, end, capacity) is
/// written at every push_back: the headers of a plain std::vector<std::vector<T>> share a 64 B
/// line, and two threads appending at once then fight over it (false sharing). The SPH
/// candidate filter took as long on 2 threads as on 1 (4.7 ms per step at 27k particles) until
/// its buffers were padded.
template <class T>
struct alignas(64) ThreadBuffer {
  T items;
};

}  // namespace fesph
