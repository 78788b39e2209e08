#pragma once
// The solve skeleton of the contact-solver backends that keep a factor equal to the matrix
// of the current contacts by rank-one changes (cholmod_contact_solver.cpp,
// eigen_contact_solver.cpp; the petsc backend's default preconditioner keeps the same factor
// and refines its application with a KSP). Internal to src/linalg.
#include <cstddef>
#include <cstdint>
#include <span>

#include "jamsim/linalg/contact_solver.hpp"

namespace jamsim::linalg {

/// A solve by an updated factor. `Factor` provides:
///  - `bool adopt(pairs, labels)`: a new candidate list (`pattern_version` changed); true when
///    the factor was carried over (relabelled), false when it was dropped;
///  - `bool has_factor()`;
///  - `int follow(pairs, in_contact)`: brings the factor to the current contacts by rank-one
///    updates and downdates, returns how many;
///  - `void factorize(pairs, in_contact)`: the factor of the current contacts from scratch;
///  - `void apply(b_x, b_y, u_x, u_y)`: u = A⁻¹ b for both halves by the factor;
///  - `int follow_and_apply(pairs, in_contact, b_x, b_y, u_x, u_y)`: `follow` then `apply`
///    (a backend may overlap the two), returns `follow`'s count;
///  - `bool residual_within(b_x, b_y, u_x, u_y)`: the true residual of u for the current
///    contacts meets the backend's tolerance.
/// Accumulated updates and downdates lose accuracy slowly, so after any change the true
/// residual is checked, and a miss factorises afresh.
template <class Factor>
SolveInfo solve_with_updated_factor(Factor& factor, std::size_t& version, std::span<const ContactPair> pairs,
                                    std::span<const std::uint8_t> in_contact, std::size_t pattern_version,
                                    std::span<const std::int32_t> labels, std::span<const double> b_x,
                                    std::span<const double> b_y, std::span<double> u_x, std::span<double> u_y) {
    SolveInfo info;
    if (pattern_version != version) {
        info.relabelled = factor.adopt(pairs, labels);
        version = pattern_version;
    }
    if (factor.has_factor()) {
        info.factor_updates = factor.follow_and_apply(pairs, in_contact, b_x, b_y, u_x, u_y);
        if (info.factor_updates == 0 && !info.relabelled) return info;
        if (factor.residual_within(b_x, b_y, u_x, u_y)) return info;
    }
    factor.factorize(pairs, in_contact);
    factor.apply(b_x, b_y, u_x, u_y);
    info.refactored = true;
    info.factor_updates = 0;
    return info;
}

}  // namespace jamsim::linalg
