#pragma once
#include "jamsim/core/system.hpp"
#include "jamsim/force/force_field.hpp"
#include "jamsim/minimize/minimizer.hpp"
#include "jamsim/observe/contact_network.hpp"

namespace jamsim {

/// Scale the cell (and the positions with it, affinely, at fixed strain) to packing fraction
/// phi. The force field's list is invalidated.
void set_packing_fraction(System& sys, ForceField& forces, double phi);

/// A minimised configuration and its contact network.
struct StaticState {
    double phi = 0.0;
    MinimizeResult minimum;
    ContactNetwork network;
    bool jammed() const { return minimum.outcome == MinimizeOutcome::ForceBalanced; }
};

/// Minimise the configuration as it is (the RAND quench when it is a random start).
StaticState quench(System& sys, ForceField& forces, Minimizer& minimizer,
                   const MinimizeCriteria& criteria);

/// The jamming density φ_J of one configuration by compression and decompression (O'Hern et
/// al. 2003): from the quenched start, step φ by Δφ towards the jamming threshold (compress
/// while unjammed, decompress while jammed), minimising after every affine step; each crossing
/// halves Δφ and reverses the direction, until Δφ < phi_tol. Every minimisation starts from
/// the previous minimum, so the configuration follows its own landscape. On return `sys` is
/// the jammed state of the final bracket (φ_J⁺, within phi_tol above the last unjammed φ), and
/// the result describes it. A minimisation that does not converge throws.
struct JammingPoint {
    double phi_j = 0.0;        ///< the jammed end of the final bracket
    double phi_unjammed = 0.0; ///< the unjammed end of the final bracket
    StaticState state;         ///< the jammed state at phi_j
    int minimizations = 0;
    std::int64_t force_evaluations = 0;  ///< over all its minimisations
};
JammingPoint find_jamming_point(System& sys, ForceField& forces, Minimizer& minimizer,
                                const MinimizeCriteria& criteria, double phi_step = 1e-3,
                                double phi_tol = 1e-6);

} // namespace jamsim
