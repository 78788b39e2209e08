#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace jamsim {

/// Per-particle state as a struct of arrays (one contiguous array per quantity).
///
/// Units: lengths in small-disk diameters d_s, forces in k_e / d_s.
/// x, y are *sheared* coordinates (see Box); fx, fy are lab-frame forces.
/// tag is the particle's index at creation; particles may be reordered in memory
/// (spatial sorting), tag restores the original order for output.
struct Particles {
    std::vector<double> x, y;       ///< sheared coordinates, shape [N]
    std::vector<double> diameter;   ///< shape [N]
    std::vector<double> fx, fy;     ///< elastic force on each particle, lab frame, shape [N]
    std::vector<std::int32_t> tag;  ///< original index, shape [N]
    /// Non-affine velocity u = v − γ̇ y x̂ (lab frame) for models that solve for it (CD0),
    /// kept here so that it follows the particles when they are reordered. d_s/τ, shape [N].
    std::vector<double> ux, uy;

    std::size_t size() const { return x.size(); }

    void resize(std::size_t n) {
        x.resize(n);
        y.resize(n);
        diameter.resize(n);
        fx.assign(n, 0.0);
        fy.assign(n, 0.0);
        tag.resize(n);
        ux.assign(n, 0.0);
        uy.assign(n, 0.0);
    }

    /// Reorder every array so that new index k holds old particle order[k].
    void permute(std::span<const std::int32_t> order);
};

/// Largest diameter in the system (0 for an empty one).
double max_diameter(const Particles& p);

}  // namespace jamsim
