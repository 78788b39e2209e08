#pragma once
// Pair loops besides the force loop (contact damping, its dissipation sums), on the kernel's
// threads over the list's fixed blocks (ForceBlocks), in the force loop's order of summation:
// the same bits on any number of threads, and up to 4096 disks those of a plain loop over
// the list in order.
#include <span>
#include <vector>

#include "jamsim/force/pair_forces.hpp"
#include "jamsim/parallel/threads.hpp"

namespace jamsim {

/// Halo slots of scatter_pairs (reused across calls).
struct HaloScratch {
    std::vector<double> x, y;
};

/// out_i = Σ_k ±v_k over the entries k = (i, j) where disk i takes part, with
/// v_k = f(k, i, j, r, touching) (a Vec2; r = r_i − r_j in the lab frame): +v for the owner
/// i, −v for the neighbour j. `out_x`, `out_y` (shape [N]) are overwritten. A disk's sum runs
/// over its block's entries in list order, then its halo slots (ForceBlocks).
template <class F>
void scatter_pairs(const NeighborList& list, const Box& box, std::span<const double> x, std::span<const double> y,
                   std::span<double> out_x, std::span<double> out_y, HaloScratch& halo, F&& f) {
    const ForceBlocks& blocks = list.blocks();
    const std::size_t n = out_x.size();
    halo.x.resize(blocks.halo_slots());
    halo.y.resize(blocks.halo_slots());
    parallel_for_blocks(blocks.count, [&](std::size_t b) {
        const std::size_t d0 = blocks.first_disk(b), d1 = std::min(n, d0 + blocks.size);
        for (std::size_t i = d0; i < d1; ++i) out_x[i] = out_y[i] = 0.0;
        auto slot = static_cast<std::size_t>(blocks.slot_first[b]);  // the next halo slot
        for_each_pair_in(list, box, x, y, static_cast<std::size_t>(blocks.entry_first[b]),
                         static_cast<std::size_t>(blocks.entry_first[b + 1]),
                         [&](std::size_t k, std::size_t i, std::size_t j, Vec2 r, bool touching) {
                             const Vec2 v = f(k, i, j, r, touching);
                             out_x[i] += v.x;
                             out_y[i] += v.y;
                             if (j >= d0 && j < d1) {
                                 out_x[j] -= v.x;
                                 out_y[j] -= v.y;
                             } else {  // 0 − v: as subtracting from a sum that starts at 0
                                 halo.x[slot] = 0.0 - v.x;
                                 halo.y[slot] = 0.0 - v.y;
                                 ++slot;
                             }
                         });
    });
    if (blocks.count > 1)
        parallel_for_blocks(blocks.count, [&](std::size_t c) {
            add_halo<false>(blocks, c, halo.x.data(), halo.y.data(), nullptr, out_x.data(), out_y.data(), nullptr);
        });
}

/// combine(...combine(P₀, P₁)..., P_last) over the list's blocks, where block b's partial P_b
/// starts from Partial{} and f(P_b, k, i, j, r, touching) adds entry k to it, in list order.
template <class Partial, class F, class Combine>
Partial reduce_pairs(const NeighborList& list, const Box& box, std::span<const double> x, std::span<const double> y,
                     F&& f, Combine&& combine) {
    const ForceBlocks& blocks = list.blocks();
    std::vector<Partial> partial(blocks.count);
    parallel_for_blocks(blocks.count, [&](std::size_t b) {
        Partial& into = partial[b];
        for_each_pair_in(
            list, box, x, y, static_cast<std::size_t>(blocks.entry_first[b]),
            static_cast<std::size_t>(blocks.entry_first[b + 1]),
            [&](std::size_t k, std::size_t i, std::size_t j, Vec2 r, bool touching) { f(into, k, i, j, r, touching); });
    });
    Partial total = partial[0];
    for (std::size_t b = 1; b < blocks.count; ++b) total = combine(total, partial[b]);
    return total;
}

}  // namespace jamsim
