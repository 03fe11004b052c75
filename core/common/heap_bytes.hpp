// SPDX-License-Identifier: MIT
// Bytes that containers hold (their capacity), for the memory figures of merit.
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

}  // namespace fesph
