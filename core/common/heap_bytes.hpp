// SPDX-License-Identifier: MIT
// Bytes that containers hold (their capacity), for the memory figures of merit, and a resize
// that keeps what they hold near what they use.
#pragma once

#include "core/common/thread_buffer.hpp"

#include <cstddef>
#include <vector>

namespace fesph {

template <class T>
std::size_t heapBytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

template <class T>
std::size_t heapBytes(const std::vector<std::vector<T>>& v) {
  std::size_t b = v.capacity() * sizeof(std::vector<T>);
  for (const std::vector<T>& inner : v) b += heapBytes(inner);
  return b;
}

template <class T>
std::size_t heapBytes(const std::vector<ThreadBuffer<std::vector<T>>>& v) {
  std::size_t b = v.capacity() * sizeof(ThreadBuffer<std::vector<T>>);
  for (const ThreadBuffer<std::vector<T>>& inner : v) b += heapBytes(inner.items);
  return b;
}

template <class T, class... Rest>
std::size_t heapBytes(const T& first, const Rest&... rest) {
  return heapBytes(first) + heapBytes(rest...);
}

/// v.resize(n), the storage grown to n and an eighth when it must grow. For arrays sized anew
/// each step that grow a little at a time (the SPH pair arrays): std::vector's doubling left
/// them holding up to twice what they use (1.9x in the particle-plate scene).
template <class T>
void resizeSnug(std::vector<T>& v, std::size_t n) {
  if (n > v.capacity()) v.reserve(n + n / 8);
  v.resize(n);
}

}  // namespace fesph
