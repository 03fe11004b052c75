// SPDX-License-Identifier: MIT
// Parallel sums with the same bits for any number of threads. An OpenMP reduction adds
// per-thread partials whose split depends on the thread count; here the split is fixed.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

namespace fesph {

/// N sums over i in [0, n) taken a block at a time: block(begin, end, s) adds the terms of
/// indices [begin, end) into s[0..N), in index order. Blocks of a fixed size are summed in
/// parallel, each alone, then the block sums in block order.
template <std::size_t N, class Block>
std::array<double, N> orderedBlockSums(std::size_t n, Block&& block) {
  constexpr std::size_t kBlock = 1024;
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::array<double, N>> partial(blocks);
// dynamic: blocks differ in cost (converted elements cluster); each block is summed alone.
// 1024: 6k elements made two blocks of 4096, one of them half empty (2 threads: 1.3x)
#pragma omp parallel for schedule(dynamic, 1) if (blocks > 1)
  for (std::size_t b = 0; b < blocks; ++b) {
    std::array<double, N> s{};
    block(b * kBlock, std::min(n, (b + 1) * kBlock), s);
    partial[b] = s;
  }
  std::array<double, N> total{};
  for (const std::array<double, N>& s : partial)
    for (std::size_t k = 0; k < N; ++k) total[k] += s[k];
  return total;
}

/// N sums over i in [0, n): term(i, s) adds the terms of index i into s[0..N).
template <std::size_t N, class Term>
std::array<double, N> orderedSums(std::size_t n, Term&& term) {
  return orderedBlockSums<N>(n, [&](std::size_t begin, std::size_t end, std::array<double, N>& s) {
    for (std::size_t i = begin; i < end; ++i) term(i, s);
  });
}

}  // namespace fesph
