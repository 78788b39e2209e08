#pragma once
// Sums over disks that give the same bits on any number of threads: the range is cut into
// fixed blocks (kReduceBlock elements, never a function of the thread count), each block's
// partial is formed in index order, and the partials are combined in block order. Up to
// kReduceBlock elements that is the plain one-pass sum.
#include <algorithm>
#include <cstddef>
#include <vector>

#include "jamsim/parallel/threads.hpp"

namespace jamsim {

/// Elements per block of a blocked reduction (a multiple of 4, so the four-lane sums of the
/// minimisers keep their lanes).
inline constexpr std::size_t kReduceBlock = 4096;

/// block(begin, end) → Partial for each block of [0, n), on the kernel's threads; returns
/// combine(...combine(p₀, p₁)..., p_last) in block order. n = 0 gives block(0, 0).
template <class Partial, class Block, class Combine>
Partial blocked_reduce(std::size_t n, Block&& block, Combine&& combine) {
    const std::size_t blocks = std::max<std::size_t>(1, (n + kReduceBlock - 1) / kReduceBlock);
    if (blocks == 1) return block(std::size_t{0}, n);
    std::vector<Partial> partial(blocks);
    parallel_for_blocks(
        blocks, [&](std::size_t b) { partial[b] = block(b * kReduceBlock, std::min(n, (b + 1) * kReduceBlock)); });
    Partial total = partial[0];
    for (std::size_t b = 1; b < blocks; ++b) total = combine(total, partial[b]);
    return total;
}

/// The largest of f(i) ≥ 0 over [0, n) (0 when n = 0), on the kernel's threads. A maximum
/// does not depend on the order it is taken in, so any split gives the same value.
template <class F> double parallel_max(std::size_t n, F&& f) {
    return blocked_reduce<double>(
        n,
        [&](std::size_t lo, std::size_t hi) {
            double m[4] = {0, 0, 0, 0};  // four lanes: no long dependency chain
            for (std::size_t i = lo; i < hi; ++i) m[i & 3] = std::max(m[i & 3], f(i));
            return std::max(std::max(m[0], m[1]), std::max(m[2], m[3]));
        },
        [](double a, double b) { return std::max(a, b); });
}

/// Sorts `v` by a strict total order `less` (no two elements equivalent), so that any
/// correct sort gives the one result: blocks of kReduceBlock sorted side by side, then merged
/// pairwise, the pairs of each round side by side.
template <class T, class Less> void parallel_sort(std::vector<T>& v, Less less) {
    const std::size_t n = v.size();
    const std::size_t blocks = (n + kReduceBlock - 1) / kReduceBlock;
    if (blocks <= 1 || kernel_threads() == 1) {
        std::sort(v.begin(), v.end(), less);
        return;
    }
    const auto at = [&](std::vector<T>& a, std::size_t i) { return a.begin() + static_cast<std::ptrdiff_t>(i); };
    parallel_for_blocks(blocks, [&](std::size_t b) {
        std::sort(at(v, b * kReduceBlock), at(v, std::min(n, (b + 1) * kReduceBlock)), less);
    });
    std::vector<T> merged(n);
    for (std::size_t width = kReduceBlock; width < n; width *= 2) {
        parallel_for_blocks((n + 2 * width - 1) / (2 * width), [&](std::size_t p) {
            const std::size_t lo = 2 * width * p, mid = std::min(n, lo + width), hi = std::min(n, lo + 2 * width);
            std::merge(at(v, lo), at(v, mid), at(v, mid), at(v, hi), at(merged, lo), less);
        });
        v.swap(merged);
    }
}

}  // namespace jamsim
