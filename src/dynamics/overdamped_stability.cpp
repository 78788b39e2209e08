// Stable time steps of the overdamped models, from the stiffest contact.
//
// Units: k_e = d_s = 1, τ = k_d d_s²/k_e; stiffnesses in k_e/d_s², k_d in k_e τ/d_s².
//
// Contact stiffness. V(r) = k_e/α (1 − r/d)^α for r < d, with d = (d_i + d_j)/2. Along the
// contact normal V''(r) = (α − 1) k_e/d² ξ^(α−2), ξ = 1 − r/d; across it V'(r)/r < 0
// (repulsion), which only lowers the Hessian. The stiffest pair is small–small (d = d_s,
// the smallest contact diameter): k_c = (α − 1) ξ^(α−2). For α = 2 (harmonic) k_c = 1 at any
// overlap and the limits below are firm; for α ≠ 2 they are evaluated at ξ = 0.1
// (kStabilityOverlap), well above the overlaps of packings near jamming. For α > 2 larger
// overlaps are stiffer, so the limit covers every overlap up to 0.1 d_s; for α < 2 vanishing
// overlaps are stiffer without bound, so no Δt is safe for every contact: such contacts carry
// forces ∝ ξ^(α−1) → 0, and the run log gets an advisory warning instead of a refusal.
//
// Linear stability. Near a state, the elastic force is f ≈ −H δx with the Hessian
// H = Σ_contacts k_c b_c b_cᵀ, b_c = (e_i − e_j) ⊗ n_c (n_c the unit contact normal).
//
// RD0 (and RD0T's drift, COOL's Langevin stage): k_d ẋ = f, so δẋ = −(H/k_d) δx. Forward
// Euler multiplies a mode by 1 − Δt λ/k_d, Heun by 1 − z + z²/2 with z = Δt λ/k_d; both stay
// within [−1, 1] exactly when Δt ≤ 2 k_d / λ. So Δt ≤ 2 k_d / λ_max(H).
// λ_max(H): for any δx, δxᵀ H δx = Σ_c k_c ((δx_i − δx_j)·n_c)² ≤ 2 Σ_c k_c ((δx_i·n_c)² +
// (δx_j·n_c)²) = 2 Σ_i δx_iᵀ S_i δx_i with S_i = Σ_{c ∋ i} k_c n_c n_cᵀ, hence
// λ_max(H) ≤ 2 max_i λ_max(S_i). A disk's 2×2 S_i has trace k_c z_i and, for z_i contacts
// spread around the disk (force balance forbids all of them on one side), λ_max(S_i) close
// to k_c z_i / 2. The largest plausible contact number of a disk in a disordered packing is
// about 6 to 8 (small disks: at most 6 small neighbours; a large disk of size ratio 1.4
// touches up to 7 small ones), which gives λ_max(S_i) ≤ 4 k_c and λ_max(H) ≤ 8 k_c: the
// figure the massive models use (ω_max² = 8 k/m, src/dynamics/sllod.cpp). Hence
//   Δt ≤ 2 k_d / (8 k_c) = k_d / (4 k_c)      (harmonic, k_d = 1: Δt ≤ 0.25 τ).
// Measured: the Hessians of harmonic packings of N = 1024 disks (size ratio 1.4) after RD0
// shear to γ = 0.5 have λ_max = 4.63, 4.96, 5.17 k_c at φ = 0.84, 0.90, 0.95 (mean contact
// numbers 3.9, 4.5, 4.9, the largest 7): true Euler limits 0.39–0.43 τ, so the bound keeps a
// factor of about 1.6 in hand and the default Δt = 0.2 τ lies inside it.
//
// CD0: force balance f − k_d A u = 0 with the contact matrix A = L + δ I (L the graph
// Laplacian of the same contacts, eq. 4.15), so δẋ = −(1/k_d) A⁻¹ H δx (with A ⊗ I₂ acting on
// both components). The eigenvalues of A⁻¹ H are the generalised ones of H v = λ A v, and
// δxᵀ H δx = Σ_c k_c ((δx_i − δx_j)·n_c)² ≤ k_c Σ_c |δx_i − δx_j|² = k_c δxᵀ (L ⊗ I₂) δx
// ≤ k_c δxᵀ (A ⊗ I₂) δx, so λ ≤ k_c whatever the contact number: the contact drag grows with
// the contacts as fast as the stiffness. Hence, for Euler and Heun alike,
//   Δt ≤ 2 k_d / k_c                            (harmonic, k_d = 1: Δt ≤ 2 τ).
// (Two disks alone in contact: λ = 2 k_c/(2 + δ), the bound is reached as δ → 0.) CD0 at
// Δt = 1.9 τ, φ = 0.9 runs stably and gives the mean pressure of Δt = 0.05 τ within 2%.
#include "jamsim/dynamics/overdamped_stability.hpp"

#include <cmath>
#include <cstdio>

namespace jamsim {

namespace {

/// Overlap at which the refused limit evaluates the stiffness (irrelevant for α = 2).
double stiffness_at_limit(double alpha) { return small_contact_stiffness(alpha, kStabilityOverlap); }

/// x rounded down to 3 significant digits: a limit a person can read in the message, and
/// never above the derived one.
double round_down_3(double x) {
    if (!(x > 0.0) || !std::isfinite(x)) return x;
    const double unit = std::pow(10.0, std::floor(std::log10(x)) - 2.0);
    return std::floor(x / unit * (1.0 + 1e-12)) * unit;
}

std::string three_digits(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", x);
    return buf;
}

std::string basis(const ReplicaParams& p, const char* form) {
    std::string out = "for " + p.model + " with kd " + show_value(p.kd) + " and alpha " + show_value(p.alpha) +
                      " (stability of the integrator: " + form +
                      ", k_c = " + three_digits(stiffness_at_limit(p.alpha)) +
                      " the stiffness of a contact of two small disks";
    if (p.alpha != 2.0) out += " at overlap " + show_value(kStabilityOverlap) + " d_s";
    return out + ")";
}

}  // namespace

double small_contact_stiffness(double alpha, double overlap) {
    if (alpha == 2.0) return 1.0;
    return (alpha - 1.0) * std::pow(overlap, alpha - 2.0);
}

double reservoir_drag_stable_dt(const ReplicaParams& p) {
    return round_down_3(2.0 * p.kd / (8.0 * stiffness_at_limit(p.alpha)));
}

double contact_drag_stable_dt(const ReplicaParams& p) { return round_down_3(2.0 * p.kd / stiffness_at_limit(p.alpha)); }

std::string reservoir_drag_dt_basis(const ReplicaParams& p) { return basis(p, "dt <= 2 kd / (8 k_c)"); }

std::string contact_drag_dt_basis(const ReplicaParams& p) {
    return basis(p, "dt <= 2 kd / k_c, the contact matrix bounds the Hessian");
}

std::string overdamped_dt_advisory(const ReplicaParams& p, double (*stable_dt)(const ReplicaParams&)) {
    if (!(p.alpha < 2.0)) return "";
    // The same limit with the stiffness at overlap 0.01 instead of 0.1.
    constexpr double kSmallOverlap = 0.01;
    const double scale =
        small_contact_stiffness(p.alpha, kStabilityOverlap) / small_contact_stiffness(p.alpha, kSmallOverlap);
    const double limit = round_down_3(stable_dt(p) * scale);
    if (p.dt <= limit) return "";
    return p.model + " with alpha " + show_value(p.alpha) +
           " < 2: contacts stiffen without bound as their overlap vanishes; dt = " + show_value(p.dt) +
           " is stable for overlaps down to " + show_value(kStabilityOverlap) +
           " d_s (dt <= " + show_value(stable_dt(p)) + ") but not down to " + show_value(kSmallOverlap) +
           " d_s (dt <= " + show_value(limit) + "): check that the results do not change at a smaller dt";
}

}  // namespace jamsim
