#pragma once
#include <memory>

#include "jamsim/linalg/contact_solver.hpp"

namespace jamsim::linalg {

/// The CD0 contact matrix solved with Eigen's sparse Cholesky (SimplicialLDLT, AMD
/// ordering). The matrix depends only on the contact set (entries are integers plus δ), so:
///  - the symbolic analysis is done once per neighbour-list pattern;
///  - while the contacts are those of the current factor, a solve is two triangular solves
///    (exact to round-off);
///  - when a few contacts have formed or broken (a low-rank change), CG preconditioned by the
///    stale factor and warm-started from the previous velocities converges in about one
///    iteration per changed contact, to ‖b − A u‖ ≤ rtol ‖b‖;
///  - when a solve needs more than `refresh_iterations` (measured best: 2 at N = 1024 and
///    16384, against 1, 3, 8 and 16), the values are refilled and refactorised.
/// Same interface and matrix as ContactSolver (PETSc).
class EigenContactSolver {
  public:
    EigenContactSolver(std::size_t n, double delta, double rtol = 1e-10);
    ~EigenContactSolver();
    EigenContactSolver(const EigenContactSolver&) = delete;
    EigenContactSolver& operator=(const EigenContactSolver&) = delete;

    SolveInfo solve(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                    std::size_t pattern_version, std::span<const double> b_x,
                    std::span<const double> b_y, std::span<double> u_x, std::span<double> u_y);

    /// Numerical factorisations so far (diagnostics, benchmarks).
    std::size_t factorizations() const;


    /// PCG iterations on a stale factor above which it is refactorised.
    static constexpr int refresh_iterations = 2;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace jamsim::linalg
