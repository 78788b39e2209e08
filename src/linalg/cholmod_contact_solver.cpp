#include "jamsim/linalg/cholmod_contact_solver.hpp"

#include "cholmod_factor.hpp"
#include "updated_factor_solve.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace jamsim::linalg {

struct CholmodContactSolver::Impl {
    CholmodUpdatedFactor factor;
    double delta, rtol;
    std::size_t version = static_cast<std::size_t>(-1);
    std::vector<double> residual;  // scratch of the residual check
    Impl(std::size_t n, double d, CholmodUpdatedFactor::Ordering o, double r) : factor(n, d, o), delta(d), rtol(r) {}

    // The factor's steps as solve_with_updated_factor calls them.
    bool adopt(std::span<const ContactPair> pairs, std::span<const std::int32_t> labels) {
        return factor.adopt(pairs, labels);
    }
    bool has_factor() const { return factor.has_factor(); }
    int follow(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact) {
        return factor.follow(pairs, in_contact);
    }
    void factorize(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact) {
        factor.factorize(pairs, in_contact);
    }
    void apply(std::span<const double> bx, std::span<const double> by, std::span<double> ux, std::span<double> uy) {
        factor.solve(bx.data(), by.data(), ux.data(), uy.data());
    }
    int follow_and_apply(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                         std::span<const double> bx, std::span<const double> by, std::span<double> ux,
                         std::span<double> uy) {
        return factor.follow_and_solve(pairs, in_contact, bx.data(), by.data(), ux.data(), uy.data());
    }
    bool residual_within(std::span<const double> bx, std::span<const double> by, std::span<const double> ux,
                         std::span<const double> uy) {
        return contact_residual_within(bx, by, ux, uy, delta, factor.contacts(), rtol, residual);
    }
};

CholmodContactSolver::CholmodContactSolver(std::size_t n, double delta, Ordering ordering, double rtol)
    : impl_(new Impl(n, delta,
                     ordering == Ordering::metis ? CholmodUpdatedFactor::Ordering::metis
                                                 : CholmodUpdatedFactor::Ordering::amd,
                     rtol)) {}

CholmodContactSolver::~CholmodContactSolver() = default;

SolveInfo CholmodContactSolver::solve(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                                      std::size_t pattern_version, std::span<const std::int32_t> labels,
                                      std::span<const double> b_x, std::span<const double> b_y, std::span<double> u_x,
                                      std::span<double> u_y) {
    Impl& m = *impl_;
    return with_factor_timings(&m.factor, [&] {
        return solve_with_updated_factor(m, m.version, pairs, in_contact, pattern_version, labels, b_x, b_y, u_x, u_y);
    });
}

}  // namespace jamsim::linalg
