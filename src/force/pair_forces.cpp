#include "jamsim/force/pair_forces.hpp"

#include <variant>

namespace jamsim {

ForceResult compute_pair_forces(const potential::SoftSphere& pot, const NeighborList& list,
                                const Box& box, std::span<const double> x,
                                std::span<const double> y, std::span<const double> diameter,
                                std::span<double> fx, std::span<double> fy) {
    return std::visit(
        [&](const auto& eval) {
            return accumulate_pair_forces(eval, list, box, x, y, diameter, fx, fy);
        },
        pot);
}

} // namespace jamsim
