#pragma once
#include <cstdint>
#include <algorithm>
#include <span>
#include <vector>

#include "jamsim/core/box.hpp"
#include "jamsim/neighbor/neighbor_list.hpp"
#include "jamsim/parallel/threads.hpp"
#include "jamsim/potential/soft_sphere.hpp"

namespace jamsim {

/// What one pass over the contacts produces besides the forces.
/// virial_ab = Σ_pairs r_ij,a f_ij,b with r_ij = r_i − r_j (lab frame) and f_ij the force
/// on i from j; units k_e (energy). For central forces it is symmetric.
struct ForceResult {
    double energy = 0.0;  ///< Σ_pairs V(r_ij), k_e
    double virial_xx = 0.0;
    double virial_xy = 0.0;
    double virial_yy = 0.0;
    std::int64_t contacts = 0;  ///< pairs with r_ij < d_ij
    bool tallied = false;       ///< false: only forces were computed (Tally::ForcesOnly)

    /// p = (P_xx + P_yy)/2 with P_ab = virial_ab / L²: positive under compression. k_e/d_s².
    double pressure(const Box& box) const { return 0.5 * (virial_xx + virial_yy) / box.area(); }
    /// σ = −P_xy: positive in steady shear with γ̇ > 0; equals (1/L²) dE/dγ. k_e/d_s².
    double shear_stress(const Box& box) const { return -virial_xy / box.area(); }
};

/// What a force evaluation must produce besides the forces. Steps that record no sample
/// ask for ForcesOnly and skip the energy, virial and contact sums.
enum class Tally { ForcesOnly, Full };

/// What one block of the force loop sums besides the forces (ForceBlocks).
struct BlockTally {
    double energy = 0.0, vxx = 0.0, vxy = 0.0, vyy = 0.0;
    std::int64_t contacts = 0;
};

/// Scratch space of the force loop (reused across calls; one per ForceField).
struct PairScratch {
    static constexpr std::size_t kChunk = 512;    ///< list entries per pass (fits in L1)
    std::vector<double> halo_x, halo_y, halo_ry;  ///< [halo slots] (ForceBlocks)
    std::vector<BlockTally> tallies;              ///< [blocks]
};

/// The evaluator over a block: f_over_r[k], and energy[k] unless energy is null, for
/// contiguous r2[k], contact[k]. Branch-free, so it vectorises.
/// Always inlined, so that the same body is compiled inside each target clone below.
template <class Evaluator>
[[gnu::always_inline]] inline void evaluate_block(const Evaluator& eval, const double* __restrict r2,
                                                  const double* __restrict contact, double* __restrict f_over_r,
                                                  double* __restrict energy, std::size_t m) {
    if (energy) {
        for (std::size_t k = 0; k < m; ++k) {
            const potential::PairTerm t = eval(r2[k], contact[k]);
            f_over_r[k] = t.force_over_r;
            energy[k] = t.energy;
        }
    } else {
        for (std::size_t k = 0; k < m; ++k) f_over_r[k] = eval(r2[k], contact[k]).force_over_r;
    }
}

/// The harmonic and Hertzian blocks are compiled twice (AVX2 and baseline x86-64) and the
/// CPU picks one at load time. Only IEEE-exact lane-wise operations are involved (sqrt,
/// division, multiply, max; no fused multiply-add), so both give the same bits.
void evaluate_block(const potential::Harmonic& eval, const double* r2, const double* contact, double* f_over_r,
                    double* energy, std::size_t m);
void evaluate_block(const potential::Hertzian& eval, const double* r2, const double* contact, double* f_over_r,
                    double* energy, std::size_t m);

/// What the force loop may record of the contacts it meets, for a model that needs them in
/// the same step (CD0's contact matrix and its affine drag), so that it need not walk the
/// pairs again: `touching[k]` = 1 when list entry k touches (r_ij < d_ij), else 0 (shape
/// [list size]), and `sum_ry[i]` = Σ_{j touching i} r_ij,y, the lab y separations r_i − r_j
/// of disk i's contacts in list order (shape [N], d_s).
struct ContactRecord {
    std::uint8_t* touching = nullptr;
    double* sum_ry = nullptr;
};

/// The lab separations r = r_owner − r_neighbour of list entries k0 .. k0 + m − 1 into rx, ry
/// and r2 (shape [m]), at the box's strain, with offsets (ox, oy) when kOffsets (see
/// accumulate_pair_forces). The one place where an entry's geometry is formed, so that every
/// force loop gets the same bits for it.
template <bool kOffsets>
[[gnu::always_inline]] inline void block_geometry(const NeighborList& list, const Box& box, const double* x,
                                                  const double* y, const double* ox, const double* oy, std::size_t k0,
                                                  std::size_t m, double* __restrict rx, double* __restrict ry,
                                                  double* __restrict r2) {
    const std::int32_t* owner = list.owner().data() + k0;
    const std::int32_t* neighbor = list.neighbor().data() + k0;
    const double* shift_x = list.shift_x().data() + k0;
    const double* shift_y = list.shift_y().data() + k0;
    const double gamma = box.strain();
    for (std::size_t k = 0; k < m; ++k) {
        const auto i = static_cast<std::size_t>(owner[k]);
        const auto j = static_cast<std::size_t>(neighbor[k]);
        double sy = y[i] - y[j] + shift_y[k];
        double sxs = x[i] - x[j] + shift_x[k];
        if constexpr (kOffsets) {
            sy += oy[i] - oy[j];
            sxs += ox[i] - ox[j];
        }
        const double sx = sxs + gamma * sy;
        rx[k] = sx;
        ry[k] = sy;
        r2[k] = sx * sx + sy * sy;
    }
}

/// One block of the force loop (ForceBlocks; see accumulate_pair_forces): zeroes the forces
/// of block b's disks, then adds the force of each of its entries into the owner and into
/// the neighbour when it lies in the block, else into the block's next halo slot. Returns the block's
/// sums (Tally::Full). Uses the caller's per-thread arrays of PairScratch::kChunk doubles.
template <Tally kTally, class Evaluator, bool kOffsets, bool kRecord>
[[gnu::always_inline]] inline BlockTally
accumulate_block(const Evaluator& eval, const NeighborList& list, const Box& box, const double* x, const double* y,
                 const double* ox, const double* oy, std::size_t b, double* fx, double* fy, PairScratch& scratch,
                 ContactRecord record, double* __restrict rx, double* __restrict ry, double* __restrict r2,
                 double* __restrict fr, double* __restrict en) {
    const ForceBlocks& blocks = list.blocks();
    const std::size_t n = list.first().size() - 1;
    const std::size_t d0 = b * blocks.size, d1 = std::min(n, d0 + blocks.size);
    for (std::size_t i = d0; i < d1; ++i) fx[i] = fy[i] = 0.0;
    if constexpr (kRecord)
        for (std::size_t i = d0; i < d1; ++i) record.sum_ry[i] = 0.0;
    double* const hx = scratch.halo_x.data();
    double* const hy = scratch.halo_y.data();
    double* const hr = scratch.halo_ry.data();
    auto slot = static_cast<std::size_t>(blocks.slot_first[b]);  // the next halo slot
    const std::int32_t* owner = list.owner().data();
    const std::int32_t* neighbor = list.neighbor().data();
    const double* contact = list.contact().data();
    const auto first = static_cast<std::int32_t>(d0);
    const auto width = static_cast<std::uint32_t>(d1 - d0);
    BlockTally t;
    const auto k_end = static_cast<std::size_t>(blocks.entry_first[b + 1]);
    for (auto k0 = static_cast<std::size_t>(blocks.entry_first[b]); k0 < k_end; k0 += PairScratch::kChunk) {
        const std::size_t m = std::min(PairScratch::kChunk, k_end - k0);
        block_geometry<kOffsets>(list, box, x, y, ox, oy, k0, m, rx, ry, r2);
        const double* dc = contact + k0;
        evaluate_block(eval, r2, dc, fr, kTally == Tally::Full ? en : nullptr, m);
        for (std::size_t k = 0; k < m; ++k) {
            const auto i = static_cast<std::size_t>(owner[k0 + k]);
            const std::int32_t j = neighbor[k0 + k];
            // In the block (about 96% of the entries: a well-predicted branch), or the next slot.
            const bool in_block = static_cast<std::uint32_t>(j - first) < width;
            const double px = fr[k] * rx[k], py = fr[k] * ry[k];
            fx[i] += px;
            fy[i] += py;
            double ry_touching = 0.0;
            if constexpr (kRecord) {
                const bool touching = r2[k] < dc[k] * dc[k];
                record.touching[k0 + k] = static_cast<std::uint8_t>(touching);
                ry_touching = ry[k] * static_cast<double>(touching);
                record.sum_ry[i] += ry_touching;
            }
            if (in_block) {
                const auto jj = static_cast<std::size_t>(j);
                fx[jj] -= px;
                fy[jj] -= py;
                if constexpr (kRecord) record.sum_ry[jj] -= ry_touching;
            } else {  // 0 − f: the same as subtracting from a sum that starts at 0
                hx[slot] = 0.0 - px;
                hy[slot] = 0.0 - py;
                if constexpr (kRecord) hr[slot] = 0.0 - ry_touching;
                ++slot;
            }
            if constexpr (kTally == Tally::Full) {
                t.energy += en[k];
                t.vxx += rx[k] * px;
                t.vxy += rx[k] * py;
                t.vyy += ry[k] * py;
                t.contacts += r2[k] < dc[k] * dc[k];
            }
        }
    }
    return t;
}

/// Adds the halo slots that belong to block c's disks: those of source blocks 0, 1, ... in
/// turn, each in list order (ForceBlocks). hr and sum_ry only when kRecord.
template <bool kRecord>
inline void add_halo(const ForceBlocks& blocks, std::size_t c, const double* hx, const double* hy, const double* hr,
                     double* fx, double* fy, double* sum_ry) {
    for (std::size_t b = 0; b < blocks.count; ++b) {
        const auto q0 = static_cast<std::size_t>(blocks.by_target_first[b * blocks.count + c]);
        const auto q1 = static_cast<std::size_t>(blocks.by_target_first[b * blocks.count + c + 1]);
        for (std::size_t q = q0; q < q1; ++q) {
            const auto s = static_cast<std::size_t>(blocks.by_target[q]);
            const auto j = static_cast<std::size_t>(blocks.halo_disk[s]);
            fx[j] += hx[s];
            fy[j] += hy[s];
            if constexpr (kRecord) sum_ry[j] += hr[s];
        }
    }
}

/// The one neighbour loop: forces (written into fx, fy), energy, virial and contact count
/// for positions (x, y) at the box's current strain, with pair evaluator `eval`.
/// The list must be valid for these positions (NeighborList::needs_rebuild is false).
///
/// It runs over the list's fixed blocks of disks (ForceBlocks), on the kernel's threads
/// when there are several blocks and threads; the result is the same bits on any number of
/// threads, because the blocks and every order of summation depend on the list alone: a
/// disk's force is its block's entries in list order, then its halo slots; a sum (energy,
/// virial, contacts) is each block's in list order, then the blocks' in block order. Up to
/// 4096 disks there is one block, and the loop is the plain one-pass scatter.
///
/// Each block runs over its entries in chunks of PairScratch::kChunk, in three passes:
/// geometry (lab separations), the evaluator on contiguous arrays (no branch, so the
/// square roots and divisions vectorise), and the scatter of forces and sums. A branch on
/// "in contact?" per pair would mispredict at a quarter of the pairs and serialise the
/// divider; this form keeps it busy.
///
/// With offsets (ox, oy non-null) the positions are x + ox, y + oy and a separation is formed
/// as (x_i − x_j + shift) + (ox_i − ox_j): a minimiser keeps x fixed (the base) and moves the
/// small offsets, so every disk gets the same absolute positional resolution, ~ε |offset|,
/// instead of ~ε |x| growing across the cell (thesis §4.7).
///
/// With kRecord the loop also fills `record` (ContactRecord), with no branch on the contact
/// test: a non-touching pair adds r_y · 0 to the sums, which leaves them unchanged.
template <Tally kTally, class Evaluator, bool kOffsets = false, bool kRecord = false>
ForceResult accumulate_pair_forces(const Evaluator& eval, const NeighborList& list, const Box& box,
                                   std::span<const double> x, std::span<const double> y, std::span<double> fx,
                                   std::span<double> fy, PairScratch& scratch, const double* ox = nullptr,
                                   const double* oy = nullptr, ContactRecord record = {}) {
    const ForceBlocks& blocks = list.blocks();
    const std::size_t slots = blocks.halo_slots();
    scratch.halo_x.resize(slots);
    scratch.halo_y.resize(slots);
    if constexpr (kRecord) scratch.halo_ry.resize(slots);
    scratch.tallies.resize(blocks.count);
    const auto count = static_cast<long>(blocks.count);
    auto run_block = [&](long b, double* rx, double* ry, double* r2, double* fr, double* en) {
        scratch.tallies[static_cast<std::size_t>(b)] = accumulate_block<kTally, Evaluator, kOffsets, kRecord>(
            eval, list, box, x.data(), y.data(), ox, oy, static_cast<std::size_t>(b), fx.data(), fy.data(), scratch,
            record, rx, ry, r2, fr, en);
    };
    // A block's halo into its disks' forces, once every block is done (in the region: the
    // barrier that ends the loop over blocks; every block and halo slot is written then).
    auto add_halo_of = [&](long c) {
        add_halo<kRecord>(blocks, static_cast<std::size_t>(c), scratch.halo_x.data(), scratch.halo_y.data(),
                          scratch.halo_ry.data(), fx.data(), fy.data(), record.sum_ry);
    };
    if (count > 1 && kernel_threads() > 1) {
        const TimedRegion timed;
#pragma omp parallel
        {
            double rx[PairScratch::kChunk], ry[PairScratch::kChunk], r2[PairScratch::kChunk];
            double fr[PairScratch::kChunk], en[PairScratch::kChunk];
#pragma omp for schedule(static)
            for (long b = 0; b < count; ++b) run_block(b, rx, ry, r2, fr, en);
#pragma omp for schedule(static)
            for (long c = 0; c < count; ++c) add_halo_of(c);
        }
    } else {
        // No parallel region at all on one thread: even a region of one thread ends in a
        // barrier whose futex wake is a system call, as dear as the whole loop at small N.
        // The blocks, then their halos: each element sees the operations in the same order.
        double rx[PairScratch::kChunk], ry[PairScratch::kChunk], r2[PairScratch::kChunk];
        double fr[PairScratch::kChunk], en[PairScratch::kChunk];
        for (long b = 0; b < count; ++b) run_block(b, rx, ry, r2, fr, en);
        if (count > 1)
            for (long c = 0; c < count; ++c) add_halo_of(c);
    }
    ForceResult out;
    out.tallied = kTally == Tally::Full;
    if constexpr (kTally == Tally::Full) {
        BlockTally sum = scratch.tallies[0];
        for (std::size_t b = 1; b < blocks.count; ++b) {
            const BlockTally& t = scratch.tallies[b];
            sum.energy += t.energy;
            sum.vxx += t.vxx;
            sum.vxy += t.vxy;
            sum.vyy += t.vyy;
            sum.contacts += t.contacts;
        }
        out.energy = sum.energy;
        out.virial_xx = sum.vxx;
        out.virial_xy = sum.vxy;
        out.virial_yy = sum.vyy;
        out.contacts = sum.contacts;
    }
    return out;
}

/// A pair in contact (r_ij < d_ij) and its lab-frame separation (r_y = [y_i − y_j]_L).
struct Contact {
    std::size_t i, j;
    double rx, ry;  ///< lab separation r_i − r_j
};

/// Calls f(k, i, j, r, touching) for the listed pairs k = (i, j) with k0 ≤ k < k1, in list
/// order, at positions (x, y) in `box` (lab separation r = r_i − r_j; touching: |r| < d_ij).
template <class List, class F>
void for_each_pair_in(const List& list, const Box& box, std::span<const double> x, std::span<const double> y,
                      std::size_t k0, std::size_t k1, F&& f) {
    const auto owner = list.owner(), neighbor = list.neighbor();
    const auto sx = list.shift_x(), sy = list.shift_y(), contact = list.contact();
    for (std::size_t k = k0; k < k1; ++k) {
        const auto i = static_cast<std::size_t>(owner[k]), j = static_cast<std::size_t>(neighbor[k]);
        const Vec2 r = box.lab(x[i] - x[j] + sx[k], y[i] - y[j] + sy[k]);
        f(k, i, j, r, norm2(r) < contact[k] * contact[k]);
    }
}

/// Calls f(k, i, j, r, touching) for every listed pair k = (i, j) at positions (x, y) in
/// `box` (lab separation r = r_i − r_j; touching: |r| < d_ij), in list order, with no branch
/// on the contact test: for loops that handle both cases arithmetically (about half the
/// pairs touch, in no pattern a branch predictor could learn). The one pair traversal beside
/// the force loop. `List` is a NeighborList or a SubList (the same entry layout).
template <class List, class F>
void for_each_pair(const List& list, const Box& box, std::span<const double> x, std::span<const double> y, F&& f) {
    for_each_pair_in(list, box, x, y, 0, list.size(), f);
}

/// Calls f(k, i, j, r) for every listed pair k = (i, j) that touches (for_each_pair's
/// touching pairs): contact dissipation (CD, CDn, CDt), contact networks.
template <class F>
void for_each_contact(const NeighborList& list, const Box& box, std::span<const double> x, std::span<const double> y,
                      F&& f) {
    for_each_pair(list, box, x, y, [&](std::size_t k, std::size_t i, std::size_t j, Vec2 r, bool touching) {
        if (touching) f(k, i, j, r);
    });
}

/// The contacts among the listed pairs, in list order (deterministic).
std::vector<Contact> find_contacts(const NeighborList& list, const Box& box, std::span<const double> x,
                                   std::span<const double> y);

/// Run-time dispatch over the registered evaluators (one instantiation each). With a
/// `record` (both pointers set) the contacts are recorded too (ContactRecord).
ForceResult compute_pair_forces(const potential::SoftSphere& pot, const NeighborList& list, const Box& box,
                                std::span<const double> x, std::span<const double> y, std::span<double> fx,
                                std::span<double> fy, PairScratch& scratch, Tally tally = Tally::Full,
                                ContactRecord record = {});

/// The same with positions split as base (x, y) + offset (ox, oy); see accumulate_pair_forces.
ForceResult compute_pair_forces_split(const potential::SoftSphere& pot, const NeighborList& list, const Box& box,
                                      std::span<const double> x, std::span<const double> y, std::span<const double> ox,
                                      std::span<const double> oy, std::span<double> fx, std::span<double> fy,
                                      PairScratch& scratch, Tally tally = Tally::Full);

}  // namespace jamsim
