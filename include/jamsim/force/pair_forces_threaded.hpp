#pragma once
// The force loop on several threads, with the bits of the one-thread loop
// (accumulate_pair_forces): every list entry's pair force is computed once, in parallel
// over blocks of entries, into per-entry arrays; then every disk sums the entries it takes
// part in, in list order (NeighborList::first and incoming), in parallel over disks, which
// is the order in which the one-thread loop adds them; the energy, virial and contact sums
// run over the entries in list order. So the result depends on the system alone, not on the
// number of threads or how the loops are split.
#include <omp.h>

#include <cstdint>

#include "jamsim/force/pair_forces.hpp"

namespace jamsim {

/// Sum, for disk i, the entry values v[k] over the entries it owns (+) and those in which it
/// is the neighbour (−), in ascending k: the one-thread loop's order of `+=` and `-=`.
inline double sum_in_list_order(std::int32_t own_first, std::size_t own_count, const std::int32_t* in,
                                std::size_t in_count, const double* v) {
    double s = 0.0;
    std::size_t a = 0, b = 0;
    while (a < own_count || b < in_count) {
        const std::int32_t ka = a < own_count ? own_first + static_cast<std::int32_t>(a) : INT32_MAX;
        const std::int32_t kb = b < in_count ? in[b] : INT32_MAX;
        if (ka < kb) {
            s += v[ka];
            ++a;
        } else {
            s -= v[kb];
            ++b;
        }
    }
    return s;
}

/// accumulate_pair_forces on the kernel's threads; the list must have its incoming entries
/// (NeighborList::ensure_incoming). Same arguments and the same bits.
template <Tally kTally, class Evaluator, bool kOffsets = false, bool kRecord = false>
ForceResult accumulate_pair_forces_threaded(const Evaluator& eval, const NeighborList& list,
                                            const Box& box, std::span<const double> x,
                                            std::span<const double> y, std::span<double> fx,
                                            std::span<double> fy, PairScratch& scratch,
                                            const double* ox = nullptr, const double* oy = nullptr,
                                            ContactRecord record = {}) {
    constexpr bool kFull = kTally == Tally::Full;
    const std::size_t n = x.size(), total = list.size();
    const std::int32_t* owner = list.owner().data();
    const std::int32_t* neighbor = list.neighbor().data();
    const double* shift_x = list.shift_x().data();
    const double* shift_y = list.shift_y().data();
    const double* contact = list.contact().data();
    const std::int32_t* first = list.first().data();
    const std::int32_t* in_first = list.incoming_first().data();
    const std::int32_t* incoming = list.incoming().data();
    const double gamma = box.strain();
    EntryScratch& entries = scratch.entries;
    entries.fx.resize(total);
    entries.fy.resize(total);
    if constexpr (kFull) {
        for (auto* v : {&entries.energy, &entries.vxx, &entries.vxy, &entries.vyy}) v->resize(total);
        entries.touching.resize(total);
    }
    if constexpr (kRecord) entries.ry_touching.resize(total);
    double* const efx = entries.fx.data();
    double* const efy = entries.fy.data();
    const auto blocks = static_cast<long>((total + PairScratch::kChunk - 1) / PairScratch::kChunk);
#pragma omp parallel
    {
        double rx[PairScratch::kChunk], ry[PairScratch::kChunk], r2[PairScratch::kChunk];
        double fr[PairScratch::kChunk], en[PairScratch::kChunk];
#pragma omp for schedule(static)
        for (long b = 0; b < blocks; ++b) {
            const std::size_t k0 = static_cast<std::size_t>(b) * PairScratch::kChunk;
            const std::size_t m = std::min(PairScratch::kChunk, total - k0);
            for (std::size_t k = 0; k < m; ++k) {
                const auto i = static_cast<std::size_t>(owner[k0 + k]);
                const auto j = static_cast<std::size_t>(neighbor[k0 + k]);
                double sy = y[i] - y[j] + shift_y[k0 + k];
                double sxs = x[i] - x[j] + shift_x[k0 + k];
                if constexpr (kOffsets) {
                    sy += oy[i] - oy[j];
                    sxs += ox[i] - ox[j];
                }
                const double sx = sxs + gamma * sy;
                rx[k] = sx;
                ry[k] = sy;
                r2[k] = sx * sx + sy * sy;
            }
            const double* dc = contact + k0;
            evaluate_block(eval, r2, dc, fr, kFull ? en : nullptr, m);
            for (std::size_t k = 0; k < m; ++k) {
                const double px = fr[k] * rx[k], py = fr[k] * ry[k];
                efx[k0 + k] = px;
                efy[k0 + k] = py;
                if constexpr (kFull) {
                    entries.energy[k0 + k] = en[k];
                    entries.vxx[k0 + k] = rx[k] * px;
                    entries.vxy[k0 + k] = rx[k] * py;
                    entries.vyy[k0 + k] = ry[k] * py;
                    entries.touching[k0 + k] = static_cast<std::uint8_t>(r2[k] < dc[k] * dc[k]);
                }
                if constexpr (kRecord) {
                    const bool touching = r2[k] < dc[k] * dc[k];
                    record.touching[k0 + k] = static_cast<std::uint8_t>(touching);
                    entries.ry_touching[k0 + k] = ry[k] * static_cast<double>(touching);
                }
            }
        }
        // (the barrier at the end of the loop above: every entry is written)
#pragma omp for schedule(static)
        for (long il = 0; il < static_cast<long>(n); ++il) {
            const auto i = static_cast<std::size_t>(il);
            const std::int32_t own = first[i];
            const auto own_count = static_cast<std::size_t>(first[i + 1] - own);
            const std::int32_t* in = incoming + in_first[i];
            const auto in_count = static_cast<std::size_t>(in_first[i + 1] - in_first[i]);
            fx[i] = sum_in_list_order(own, own_count, in, in_count, efx);
            fy[i] = sum_in_list_order(own, own_count, in, in_count, efy);
            if constexpr (kRecord)
                record.sum_ry[i] = sum_in_list_order(own, own_count, in, in_count, entries.ry_touching.data());
        }
    }
    ForceResult out;
    out.tallied = kFull;
    if constexpr (kFull) {  // in list order, as the one-thread loop sums them
        double energy = 0.0, vxx = 0.0, vxy = 0.0, vyy = 0.0;
        std::int64_t contacts = 0;
        for (std::size_t k = 0; k < total; ++k) {
            energy += entries.energy[k];
            vxx += entries.vxx[k];
            vxy += entries.vxy[k];
            vyy += entries.vyy[k];
            contacts += entries.touching[k];
        }
        out.energy = energy;
        out.virial_xx = vxx;
        out.virial_xy = vxy;
        out.virial_yy = vyy;
        out.contacts = contacts;
    }
    return out;
}

} // namespace jamsim
