#pragma once
#include <cstdint>
#include <span>

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

    /// p = (P_xx + P_yy)/2 with P_ab = virial_ab / L²: positive under compression. k_e/d_s².
    double pressure(const Box& box) const { return 0.5 * (virial_xx + virial_yy) / box.area(); }
    /// σ = −P_xy: positive in steady shear with γ̇ > 0; equals (1/L²) dE/dγ. k_e/d_s².
    double shear_stress(const Box& box) const { return -virial_xy / box.area(); }
};

/// The one neighbour loop: forces (written into fx, fy), energy, virial and contact count
/// for positions (x, y) at the box's current strain, with pair evaluator `eval`.
/// The list must be valid for these positions (NeighborList::needs_rebuild is false).
template <class Evaluator>
ForceResult accumulate_pair_forces(const Evaluator& eval, const NeighborList& list,
                                   const Box& box, std::span<const double> x,
                                   std::span<const double> y, std::span<const double> diameter,
                                   std::span<double> fx, std::span<double> fy) {
    const std::size_t n = x.size();
    for (std::size_t i = 0; i < n; ++i) fx[i] = fy[i] = 0.0;
    const std::int32_t* first = list.first().data();
    const std::int32_t* neighbor = list.neighbor().data();
    const double* shift_x = list.shift_x().data();
    const double* shift_y = list.shift_y().data();
    const double gamma = box.strain();
    ForceResult out;
    double energy = 0.0, vxx = 0.0, vxy = 0.0, vyy = 0.0;
    std::int64_t contacts = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double xi = x[i], yi = y[i], di = diameter[i];
        double fxi = 0.0, fyi = 0.0;
        for (std::int32_t k = first[i]; k < first[i + 1]; ++k) {
            const auto j = static_cast<std::size_t>(neighbor[k]);
            const double ry = yi - y[j] + shift_y[k];
            const double rx = xi - x[j] + shift_x[k] + gamma * ry;
            const double r2 = rx * rx + ry * ry;
            const double dij = 0.5 * (di + diameter[j]);
            if (r2 >= dij * dij) continue;
            const potential::PairTerm t = eval(r2, dij);
            const double px = t.force_over_r * rx, py = t.force_over_r * ry;
            fxi += px;
            fyi += py;
            fx[j] -= px;
            fy[j] -= py;
            energy += t.energy;
            vxx += rx * px;
            vxy += rx * py;
            vyy += ry * py;
            ++contacts;
        }
        fx[i] += fxi;
        fy[i] += fyi;
    }
    out.energy = energy;
    out.virial_xx = vxx;
    out.virial_xy = vxy;
    out.virial_yy = vyy;
    out.contacts = contacts;
    return out;
}

/// Run-time dispatch over the registered evaluators (one instantiation each).
ForceResult compute_pair_forces(const potential::SoftSphere& pot, const NeighborList& list,
                                const Box& box, std::span<const double> x,
                                std::span<const double> y, std::span<const double> diameter,
                                std::span<double> fx, std::span<double> fy);

} // namespace jamsim
