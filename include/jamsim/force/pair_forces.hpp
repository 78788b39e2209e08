#pragma once
#include <cstdint>
#include <algorithm>
#include <span>
#include <vector>

#include "jamsim/core/box.hpp"
#include "jamsim/neighbor/neighbor_list.hpp"
#include "jamsim/potential/soft_sphere.hpp"

namespace jamsim {

/// What one pass over the contacts produces besides the forces.
/// virial_ab = Σ_pairs r_ij,a f_ij,b with r_ij = r_i − r_j (lab frame) and f_ij the force
/// on i from j; units k_e (energy). For central forces it is symmetric.
struct ForceResult {
    double energy = 0.0;      ///< Σ_pairs V(r_ij), k_e
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

/// Per-entry results of the threaded force loop (shape [list size]; pair_forces_threaded.hpp).
struct EntryScratch {
    std::vector<double> f;                      ///< force on the owner from the neighbour, (x, y) pairs
    std::vector<double> energy, vxx, vxy, vyy;  ///< Tally::Full
    std::vector<std::uint8_t> touching;         ///< Tally::Full
    std::vector<double> ry_touching;            ///< ContactRecord: r_y of a touching entry, else 0
};

/// Scratch space of the force loop (reused across calls; one per ForceField).
struct PairScratch {
    static constexpr std::size_t kChunk = 512;  ///< list entries per block (fits in L1)
    std::vector<double> rx = block(), ry = block(), r2 = block(), f_over_r = block(),
                        energy = block();
    EntryScratch entries;  ///< the threaded loop's

  private:
    static std::vector<double> block() { return std::vector<double>(kChunk); }
};

/// The evaluator over a block: f_over_r[k], and energy[k] unless energy is null, for
/// contiguous r2[k], contact[k]. Branch-free, so it vectorises.
/// Always inlined, so that the same body is compiled inside each target clone below.
template <class Evaluator>
[[gnu::always_inline]] inline void evaluate_block(const Evaluator& eval,
                                                  const double* __restrict r2,
                                                  const double* __restrict contact,
                                                  double* __restrict f_over_r,
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
void evaluate_block(const potential::Harmonic& eval, const double* r2, const double* contact,
                    double* f_over_r, double* energy, std::size_t m);
void evaluate_block(const potential::Hertzian& eval, const double* r2, const double* contact,
                    double* f_over_r, double* energy, std::size_t m);

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
                                                  const double* y, const double* ox, const double* oy,
                                                  std::size_t k0, std::size_t m, double* __restrict rx,
                                                  double* __restrict ry, double* __restrict r2) {
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

/// The one neighbour loop: forces (written into fx, fy), energy, virial and contact count
/// for positions (x, y) at the box's current strain, with pair evaluator `eval`.
/// The list must be valid for these positions (NeighborList::needs_rebuild is false).
///
/// It runs over the flat list in blocks of PairScratch::kChunk entries, in three passes:
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
ForceResult accumulate_pair_forces(const Evaluator& eval, const NeighborList& list,
                                   const Box& box, std::span<const double> x,
                                   std::span<const double> y,
                                   std::span<double> fx, std::span<double> fy,
                                   PairScratch& scratch, const double* ox = nullptr,
                                   const double* oy = nullptr, ContactRecord record = {}) {
    const std::size_t n = x.size();
    for (std::size_t i = 0; i < n; ++i) fx[i] = fy[i] = 0.0;
    if constexpr (kRecord)
        for (std::size_t i = 0; i < n; ++i) record.sum_ry[i] = 0.0;
    const std::int32_t* owner = list.owner().data();
    const std::int32_t* neighbor = list.neighbor().data();
    double* const rx = scratch.rx.data();
    double* const ry = scratch.ry.data();
    double* const r2 = scratch.r2.data();
    const double* contact = list.contact().data();
    double* const fr = scratch.f_over_r.data();
    double* const en = scratch.energy.data();
    double energy = 0.0, vxx = 0.0, vxy = 0.0, vyy = 0.0;
    std::int64_t contacts = 0;
    const std::size_t total = list.size();
    for (std::size_t k0 = 0; k0 < total; k0 += PairScratch::kChunk) {
        const std::size_t m = std::min(PairScratch::kChunk, total - k0);
        block_geometry<kOffsets>(list, box, x.data(), y.data(), ox, oy, k0, m, rx, ry, r2);
        const double* dc = contact + k0;
        evaluate_block(eval, r2, dc, fr, kTally == Tally::Full ? en : nullptr, m);
        for (std::size_t k = 0; k < m; ++k) {
            const auto i = static_cast<std::size_t>(owner[k0 + k]);
            const auto j = static_cast<std::size_t>(neighbor[k0 + k]);
            const double px = fr[k] * rx[k], py = fr[k] * ry[k];
            fx[i] += px;
            fy[i] += py;
            fx[j] -= px;
            fy[j] -= py;
            if constexpr (kRecord) {
                const bool touching = r2[k] < dc[k] * dc[k];
                record.touching[k0 + k] = static_cast<std::uint8_t>(touching);
                const double ry_touching = ry[k] * static_cast<double>(touching);
                record.sum_ry[i] += ry_touching;
                record.sum_ry[j] -= ry_touching;
            }
            if constexpr (kTally == Tally::Full) {
                energy += en[k];
                vxx += rx[k] * px;
                vxy += rx[k] * py;
                vyy += ry[k] * py;
                contacts += r2[k] < dc[k] * dc[k];
            }
        }
    }
    ForceResult out;
    out.energy = energy;
    out.virial_xx = vxx;
    out.virial_xy = vxy;
    out.virial_yy = vyy;
    out.contacts = contacts;
    out.tallied = kTally == Tally::Full;
    return out;
}

/// A pair in contact (r_ij < d_ij) and its lab-frame separation (r_y = [y_i − y_j]_L).
struct Contact {
    std::size_t i, j;
    double rx, ry;  ///< lab separation r_i − r_j
};

/// Calls f(k, i, j, r, touching) for every listed pair k = (i, j) at positions (x, y) in
/// `box` (lab separation r = r_i − r_j; touching: |r| < d_ij), in list order, with no branch
/// on the contact test: for loops that handle both cases arithmetically (about half the
/// pairs touch, in no pattern a branch predictor could learn). The one pair traversal beside
/// the force loop. `List` is a NeighborList or a SubList (the same entry layout).
template <class List, class F>
void for_each_pair(const List& list, const Box& box, std::span<const double> x,
                   std::span<const double> y, F&& f) {
    const auto owner = list.owner(), neighbor = list.neighbor();
    const auto sx = list.shift_x(), sy = list.shift_y(), contact = list.contact();
    for (std::size_t k = 0; k < list.size(); ++k) {
        const auto i = static_cast<std::size_t>(owner[k]), j = static_cast<std::size_t>(neighbor[k]);
        const Vec2 r = box.lab(x[i] - x[j] + sx[k], y[i] - y[j] + sy[k]);
        f(k, i, j, r, norm2(r) < contact[k] * contact[k]);
    }
}

/// Calls f(k, i, j, r) for every listed pair k = (i, j) that touches (for_each_pair's
/// touching pairs): contact dissipation (CD, CDn, CDt), contact networks.
template <class F>
void for_each_contact(const NeighborList& list, const Box& box, std::span<const double> x,
                      std::span<const double> y, F&& f) {
    for_each_pair(list, box, x, y, [&](std::size_t k, std::size_t i, std::size_t j, Vec2 r, bool touching) {
        if (touching) f(k, i, j, r);
    });
}

/// The contacts among the listed pairs, in list order (deterministic).
std::vector<Contact> find_contacts(const NeighborList& list, const Box& box,
                                   std::span<const double> x, std::span<const double> y);

/// Run-time dispatch over the registered evaluators (one instantiation each). With a
/// `record` (both pointers set) the contacts are recorded too (ContactRecord).
ForceResult compute_pair_forces(const potential::SoftSphere& pot, const NeighborList& list,
                                const Box& box, std::span<const double> x,
                                std::span<const double> y,
                                std::span<double> fx, std::span<double> fy,
                                PairScratch& scratch, Tally tally = Tally::Full,
                                ContactRecord record = {});

/// The same with positions split as base (x, y) + offset (ox, oy); see accumulate_pair_forces.
ForceResult compute_pair_forces_split(const potential::SoftSphere& pot, const NeighborList& list,
                                      const Box& box, std::span<const double> x,
                                      std::span<const double> y, std::span<const double> ox,
                                      std::span<const double> oy, std::span<double> fx,
                                      std::span<double> fy, PairScratch& scratch,
                                      Tally tally = Tally::Full);

} // namespace jamsim
