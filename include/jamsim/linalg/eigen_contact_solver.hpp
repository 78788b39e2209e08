#pragma once
#include <memory>

#include "jamsim/linalg/contact_solver.hpp"

namespace jamsim::linalg {

/// The CD0 contact matrix solved with a sparse LDLᵀ factorisation (Eigen's SimplicialLDLT
/// with AMD ordering for the analysis and fresh factorisations). The matrix depends only on
/// the contact set (entries are integers plus δ), and the pattern analysed for a new candidate
/// list holds every pair that may touch, so:
///  - a solve is one pass of triangular solves for both right-hand sides;
///  - a contact that forms or breaks is a rank-one change of A, applied to the factor in place
///    (update/downdate along the elimination tree) instead of refactorising;
///  - after changes the true residual ‖b − A u‖ ≤ rtol ‖b‖ is checked, and the factor is
///    rebuilt from scratch if round-off accumulated by the changes makes it miss;
///  - a new candidate list starts with a fresh analysis and factorisation.
/// Same interface and matrix as ContactSolver (PETSc).
class EigenContactSolver final : public ContactSolver {
  public:
    EigenContactSolver(std::size_t n, double delta, double rtol = 1e-10);
    ~EigenContactSolver() override;
    EigenContactSolver(const EigenContactSolver&) = delete;
    EigenContactSolver& operator=(const EigenContactSolver&) = delete;

    SolveInfo solve(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                    std::size_t pattern_version, std::span<const std::int32_t> labels, std::span<const double> b_x,
                    std::span<const double> b_y, std::span<double> u_x, std::span<double> u_y) override;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace jamsim::linalg
