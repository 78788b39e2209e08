#pragma once
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <variant>

namespace jamsim::potential {

/// Result of one pair evaluation.
struct PairTerm {
    double force_over_r;  ///< |F|/r in k_e/d_s²; positive = repulsive (F_i = force_over_r * r_ij)
    double energy;        ///< V(r) in k_e
};

// Pure pair evaluators for V(r) = k_e/α (1 − r/d)^α, r < d (thesis eq. 4.7).
// Each takes r² > 0 and the contact distance d = (d_i + d_j)/2 and returns exactly zero
// force and energy for r ≥ d, without a branch: the force loop calls it for every listed
// pair, which is faster than a data-dependent branch that mispredicts at ~25% of pairs.
// The magnitude of the repulsion is F = −dV/dr = (k_e/d) (1 − r/d)^(α−1).

/// α = 2: one-sided harmonic springs. With s = d − r: |F|/r = k_e s / (d² r),
/// V = k_e s² / (2 d²) = ½ (|F|/r) r s: one square root and one division per contact.
struct Harmonic {
    double ke = 1.0;
    double alpha() const { return 2.0; }
    PairTerm operator()(double r2, double d) const {
        const double r = std::sqrt(r2);
        const double s = std::max(d - r, 0.0);
        const double f_over_r = ke * s / (d * d * r);
        return {f_over_r, 0.5 * f_over_r * r * s};
    }
};

/// α = 5/2: Hertzian contacts. With s = d − r: |F|/r = k_e s √(s d) / (d³ r),
/// V = 0.4 k_e (s/d)^{5/2} = 0.4 (|F|/r) r s.
struct Hertzian {
    double ke = 1.0;
    double alpha() const { return 2.5; }
    PairTerm operator()(double r2, double d) const {
        const double r = std::sqrt(r2);
        const double s = std::max(d - r, 0.0);
        const double f_over_r = ke * s * std::sqrt(s * d) / (d * d * d * r);
        return {f_over_r, 0.4 * f_over_r * r * s};
    }
};

/// Any α > 1.
struct PowerLaw {
    double ke = 1.0;
    double exponent = 2.0;
    double alpha() const { return exponent; }
    PairTerm operator()(double r2, double d) const {
        const double r = std::sqrt(r2);
        const double overlap = std::max(1.0 - r / d, 0.0);
        const double s = std::pow(overlap, exponent - 1.0);
        return {ke * s / (d * r), ke / exponent * s * overlap};
    }
};

/// The evaluator chosen at run time; the force loop is instantiated once per alternative.
using SoftSphere = std::variant<Harmonic, Hertzian, PowerLaw>;

/// Registry: the evaluator for exponent α (dedicated fast kernels for 2 and 2.5).
inline SoftSphere make_soft_sphere(double alpha, double ke = 1.0) {
    if (!(alpha > 1.0) || !std::isfinite(alpha))
        throw std::invalid_argument("potential exponent alpha must be > 1, got " + std::to_string(alpha));
    if (alpha == 2.0) return Harmonic{ke};
    if (alpha == 2.5) return Hertzian{ke};
    return PowerLaw{ke, alpha};
}

}  // namespace jamsim::potential
