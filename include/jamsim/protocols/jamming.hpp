#pragma once
#include <functional>
#include <vector>

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
StaticState quench(System& sys, ForceField& forces, Minimizer& minimizer, const MinimizeCriteria& criteria);

/// The state of a φ_J search between two minimisations: what it needs, besides the
/// configuration, to continue bitwise (a checkpoint stores it as `pack()`).
struct JammingSearch {
    double phi = 0.0;                    ///< packing fraction of the configuration
    double step = 0.0;                   ///< current Δφ
    bool crossed = false;                ///< the threshold has been bracketed at least once
    bool jammed = false;                 ///< the last minimum was jammed
    double phi_unjammed = 0.0;           ///< the last unjammed φ
    int minimizations = 0;               ///< done so far
    std::int64_t force_evaluations = 0;  ///< over them
    std::vector<double> pack() const;
    /// Throws std::invalid_argument when `v` is not a packed search.
    static JammingSearch unpack(const std::vector<double>& v);
};

/// The jamming density φ_J of one configuration by compression and decompression (O'Hern et
/// al. 2003): from the quenched start, step φ by Δφ towards the jamming threshold (compress
/// while unjammed, decompress while jammed), minimising after every affine step; each crossing
/// halves Δφ and reverses the direction, until Δφ < phi_tol. Every minimisation starts from
/// the previous minimum, so the configuration follows its own landscape. On return `sys` is
/// the jammed state of the final bracket (φ_J⁺, within phi_tol above the last unjammed φ), and
/// the result describes it. A minimisation that does not converge throws.
///
/// Resumable: `before_minimisation` is called before every minimisation but the first, with
/// the configuration already at the new φ; a search given that state as `resume` (and the
/// same configuration) continues bitwise, provided the caller drops the force field's caches
/// there whether or not it stops.
struct JammingPoint {
    double phi_j = 0.0;         ///< the jammed end of the final bracket
    double phi_unjammed = 0.0;  ///< the unjammed end of the final bracket
    StaticState state;          ///< the jammed state at phi_j
    int minimizations = 0;
    std::int64_t force_evaluations = 0;  ///< over all its minimisations (before a resume too)
};
JammingPoint find_jamming_point(System& sys, ForceField& forces, Minimizer& minimizer, const MinimizeCriteria& criteria,
                                double phi_step = 1e-3, double phi_tol = 1e-6, const JammingSearch* resume = nullptr,
                                const std::function<void(const JammingSearch&)>& before_minimisation = {});

}  // namespace jamsim
