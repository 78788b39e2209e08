#pragma once
#include <memory>

#include "jamsim/linalg/contact_solver.hpp"

namespace jamsim::linalg {

/// The CD0 contact matrix solved directly with Eigen's sparse Cholesky (SimplicialLDLT,
/// AMD ordering). The symbolic analysis is done once per neighbour-list pattern; every step
/// refills the values, refactorises and solves for u_x and u_y. Same interface and matrix as
/// ContactSolver (PETSc), exact to round-off, no tolerance to choose.
class EigenContactSolver {
  public:
    EigenContactSolver(std::size_t n, double delta);
    ~EigenContactSolver();
    EigenContactSolver(const EigenContactSolver&) = delete;
    EigenContactSolver& operator=(const EigenContactSolver&) = delete;

    SolveInfo solve(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                    std::size_t pattern_version, std::span<const double> b_x,
                    std::span<const double> b_y, std::span<double> u_x, std::span<double> u_y);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace jamsim::linalg
