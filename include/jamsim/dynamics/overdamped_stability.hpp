#pragma once
// The largest stable time step of the overdamped models (RD0, RD0T, COOL's Langevin stage:
// reservoir drag; CD0: contact drag), from the stiffest contact. The derivation is in
// src/dynamics/overdamped_stability.cpp.
#include <string>

#include "jamsim/params/parameters.hpp"

namespace jamsim {

/// Overlap ξ = 1 − r/d (in units of the pair diameter) at which the stiffness of a
/// non-harmonic contact is evaluated for the refused limit (α ≠ 2: the stiffness depends on
/// the overlap). Far above the overlaps of packings near jamming (ξ ~ 1e-3 to 1e-2).
inline constexpr double kStabilityOverlap = 0.1;

/// Stiffness V''(r) of a contact between two small disks (d = d_s, the stiffest pair) at
/// overlap ξ, in k_e/d_s²: (α − 1) ξ^(α−2); for α = 2 it is 1 whatever the overlap.
double small_contact_stiffness(double alpha, double overlap);

/// Reservoir drag (RD0, RD0T, COOL): Δt ≤ 2 k_d / λ_max(H) with λ_max(H) = 8 k_c, in τ.
double reservoir_drag_stable_dt(const ReplicaParams& p);
/// Contact drag (CD0): Δt ≤ 2 k_d / k_c, in τ (the contact matrix bounds the Hessian).
double contact_drag_stable_dt(const ReplicaParams& p);

/// What the limit rests on, for the refusal: "for RD0 with kd 1 and alpha 2: ...".
std::string reservoir_drag_dt_basis(const ReplicaParams& p);
std::string contact_drag_dt_basis(const ReplicaParams& p);

/// An advisory note when the limit may not protect the run (α < 2: the stiffness grows
/// without bound as the overlap vanishes, and dt exceeds the limit at overlap 0.01); "" when
/// none. Printed once in the run log, not refused.
std::string overdamped_dt_advisory(const ReplicaParams& p, double (*stable_dt)(const ReplicaParams&));

}  // namespace jamsim
