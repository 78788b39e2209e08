#include "jamsim/force/pair_forces.hpp"

#include <variant>

namespace jamsim {

ForceResult compute_pair_forces(const potential::SoftSphere& pot, const NeighborList& list,
                                const Box& box, std::span<const double> x,
                                std::span<const double> y, std::span<const double> diameter,
                                std::span<double> fx, std::span<double> fy,
                                PairScratch& scratch, Tally tally) {
    return std::visit(
        [&](const auto& eval) {
            return tally == Tally::Full
                       ? accumulate_pair_forces<Tally::Full>(eval, list, box, x, y, diameter, fx,
                                                            fy, scratch)
                       : accumulate_pair_forces<Tally::ForcesOnly>(eval, list, box, x, y,
                                                                  diameter, fx, fy, scratch);
        },
        pot);
}

} // namespace jamsim
