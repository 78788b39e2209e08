#include "jamsim/linalg/cholmod_contact_solver.hpp"

#include "cholmod_factor.hpp"

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

    void solve(std::span<const double> bx, std::span<const double> by, std::span<double> ux, std::span<double> uy) {
        factor.solve(bx.data(), by.data(), ux.data(), uy.data());
    }
    /// The backend's solve (CholmodContactSolver::solve adds the factor's timings).
    SolveInfo run(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                  std::size_t pattern_version, std::span<const std::int32_t> labels, std::span<const double> b_x,
                  std::span<const double> b_y, std::span<double> u_x, std::span<double> u_y);
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
    return with_factor_timings(&m.factor,
                               [&] { return m.run(pairs, in_contact, pattern_version, labels, b_x, b_y, u_x, u_y); });
}

SolveInfo CholmodContactSolver::Impl::run(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                                          std::size_t pattern_version, std::span<const std::int32_t> labels,
                                          std::span<const double> b_x, std::span<const double> b_y,
                                          std::span<double> u_x, std::span<double> u_y) {
    Impl& m = *this;
    SolveInfo info;
    if (pattern_version != m.version) {
        info.relabelled = m.factor.adopt(pairs, labels);
        m.version = pattern_version;
    }
    if (m.factor.has_factor()) {  // bring the factor to the current contacts
        info.factor_updates = m.factor.follow(pairs, in_contact);
        m.solve(b_x, b_y, u_x, u_y);
        if (info.factor_updates == 0 && !info.relabelled) return info;
        if (contact_residual_within(b_x, b_y, u_x, u_y, m.delta, m.factor.contacts(), m.rtol, m.residual)) return info;
    }
    m.factor.factorize(pairs, in_contact);
    m.solve(b_x, b_y, u_x, u_y);
    info.refactored = true;
    info.factor_updates = 0;
    return info;
}

}  // namespace jamsim::linalg
