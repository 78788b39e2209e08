#include "jamsim/force/pair_forces.hpp"

#include "jamsim/parallel/threads.hpp"

#include <variant>

namespace jamsim {

#if defined(__x86_64__) && defined(__GNUC__)
#define JAMSIM_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define JAMSIM_CLONES
#endif

JAMSIM_CLONES void evaluate_block(const potential::Harmonic& eval, const double* r2, const double* contact,
                                  double* f_over_r, double* energy, std::size_t m) {
    evaluate_block<potential::Harmonic>(eval, r2, contact, f_over_r, energy, m);
}

JAMSIM_CLONES void evaluate_block(const potential::Hertzian& eval, const double* r2, const double* contact,
                                  double* f_over_r, double* energy, std::size_t m) {
    evaluate_block<potential::Hertzian>(eval, r2, contact, f_over_r, energy, m);
}

std::vector<Contact> find_contacts(const NeighborList& list, const Box& box, std::span<const double> x,
                                   std::span<const double> y) {
    std::vector<Contact> out;
    for_each_contact(list, box, x, y, [&](std::size_t, std::size_t i, std::size_t j, Vec2 r) {
        out.push_back({i, j, r.x, r.y});
    });
    return out;
}

namespace {
template <Tally kTally, class E, bool kOffsets, bool kRecord>
ForceResult pair_forces(const E& eval, const NeighborList& list, const Box& box, std::span<const double> x,
                        std::span<const double> y, std::span<double> fx, std::span<double> fy, PairScratch& scratch,
                        const double* ox, const double* oy, ContactRecord record) {
    return accumulate_pair_forces<kTally, E, kOffsets, kRecord>(eval, list, box, x, y, fx, fy, scratch, ox, oy, record);
}
}  // namespace

ForceResult compute_pair_forces(const potential::SoftSphere& pot, const NeighborList& list, const Box& box,
                                std::span<const double> x, std::span<const double> y, std::span<double> fx,
                                std::span<double> fy, PairScratch& scratch, Tally tally, ContactRecord record) {
    const bool recording = record.touching != nullptr && record.sum_ry != nullptr;
    return std::visit(
        [&](const auto& eval) {
            using E = std::decay_t<decltype(eval)>;
            if (recording)
                return tally == Tally::Full
                           ? pair_forces<Tally::Full, E, false, true>(eval, list, box, x, y, fx, fy, scratch, nullptr,
                                                                      nullptr, record)
                           : pair_forces<Tally::ForcesOnly, E, false, true>(eval, list, box, x, y, fx, fy, scratch,
                                                                            nullptr, nullptr, record);
            return tally == Tally::Full ? pair_forces<Tally::Full, E, false, false>(eval, list, box, x, y, fx, fy,
                                                                                    scratch, nullptr, nullptr, {})
                                        : pair_forces<Tally::ForcesOnly, E, false, false>(
                                              eval, list, box, x, y, fx, fy, scratch, nullptr, nullptr, {});
        },
        pot);
}

ForceResult compute_pair_forces_split(const potential::SoftSphere& pot, const NeighborList& list, const Box& box,
                                      std::span<const double> x, std::span<const double> y, std::span<const double> ox,
                                      std::span<const double> oy, std::span<double> fx, std::span<double> fy,
                                      PairScratch& scratch, Tally tally) {
    return std::visit(
        [&](const auto& eval) {
            using E = std::decay_t<decltype(eval)>;
            return tally == Tally::Full ? pair_forces<Tally::Full, E, true, false>(eval, list, box, x, y, fx, fy,
                                                                                   scratch, ox.data(), oy.data(), {})
                                        : pair_forces<Tally::ForcesOnly, E, true, false>(
                                              eval, list, box, x, y, fx, fy, scratch, ox.data(), oy.data(), {});
        },
        pot);
}

}  // namespace jamsim
