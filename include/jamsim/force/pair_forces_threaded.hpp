#pragma once
// The force loop on several threads, with the bits of the one-thread loop
// (accumulate_pair_forces): every list entry's pair force is computed once, in parallel
// over blocks of entries, into per-entry arrays; then every disk sums the entries it takes
// part in, in list order (NeighborList::incidence), in parallel over disks, which
// is the order in which the one-thread loop adds them; the energy, virial and contact sums
// run over the entries in list order. So the result depends on the system alone, not on the
// number of threads or how the loops are split.
#include <omp.h>

#include <cstdint>

#include "jamsim/force/pair_forces.hpp"

namespace jamsim {

/// accumulate_pair_forces on the kernel's threads; the list must have its incidence
/// (NeighborList::ensure_incidence). Same arguments and the same bits.
template <Tally kTally, class Evaluator, bool kOffsets = false, bool kRecord = false>
ForceResult accumulate_pair_forces_threaded(const Evaluator& eval, const NeighborList& list,
                                            const Box& box, std::span<const double> x,
                                            std::span<const double> y, std::span<double> fx,
                                            std::span<double> fy, PairScratch& scratch,
                                            const double* ox = nullptr, const double* oy = nullptr,
                                            ContactRecord record = {}) {
    constexpr bool kFull = kTally == Tally::Full;
    const std::size_t n = x.size(), total = list.size();
    const double* contact = list.contact().data();
    const std::int32_t* inc_first = list.incidence_first().data();
    const std::int32_t* incidence = list.incidence().data();
    EntryScratch& entries = scratch.entries;
    entries.f.resize(2 * total);
    if constexpr (kFull) {
        for (auto* v : {&entries.energy, &entries.vxx, &entries.vxy, &entries.vyy}) v->resize(total);
        entries.touching.resize(total);
    }
    if constexpr (kRecord) entries.ry_touching.resize(total);
    double* const ef = entries.f.data();  // (fx, fy) of entry k at 2k, 2k + 1: one line per gather
    const auto blocks = static_cast<long>((total + PairScratch::kChunk - 1) / PairScratch::kChunk);
#pragma omp parallel
    {
        double rx[PairScratch::kChunk], ry[PairScratch::kChunk], r2[PairScratch::kChunk];
        double fr[PairScratch::kChunk], en[PairScratch::kChunk];
#pragma omp for schedule(static)
        for (long b = 0; b < blocks; ++b) {
            const std::size_t k0 = static_cast<std::size_t>(b) * PairScratch::kChunk;
            const std::size_t m = std::min(PairScratch::kChunk, total - k0);
            block_geometry<kOffsets>(list, box, x.data(), y.data(), ox, oy, k0, m, rx, ry, r2);
            const double* dc = contact + k0;
            evaluate_block(eval, r2, dc, fr, kFull ? en : nullptr, m);
            for (std::size_t k = 0; k < m; ++k) {
                const double px = fr[k] * rx[k], py = fr[k] * ry[k];
                ef[2 * (k0 + k)] = px;
                ef[2 * (k0 + k) + 1] = py;
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
            // Each entry once, in list order, +f where i owns it, −f where it is the
            // neighbour: s + (−1·f) is exactly the one-thread loop's s − f.
            double sx = 0.0, sy = 0.0, sr = 0.0;
            for (std::int32_t q = inc_first[i]; q < inc_first[i + 1]; ++q) {
                const std::int32_t e = incidence[q];
                const auto k = static_cast<std::size_t>(e >= 0 ? e : ~e);
                const double sign = e >= 0 ? 1.0 : -1.0;
                sx += sign * ef[2 * k];
                sy += sign * ef[2 * k + 1];
                if constexpr (kRecord) sr += sign * entries.ry_touching[k];
            }
            fx[i] = sx;
            fy[i] = sy;
            if constexpr (kRecord) record.sum_ry[i] = sr;
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
