#pragma once
#include <string>

#include "jamsim/linalg/contact_solver.hpp"

namespace jamsim::linalg {

/// Solves A u = b for the CD0 contact matrix A (thesis eq. 4.15): A_ii = z_i + δ,
/// A_ij = −1 per contact, with PETSc KSP on PETSC_COMM_SELF.
///
/// The Mat (SeqAIJ) has the sparsity pattern of the *neighbour list* (every pair that may
/// touch before the next list rebuild), with explicit zeros for pairs not in contact, so its
/// pattern changes only when the list is rebuilt; the values are refilled every step. The
/// KSP is reused, warm-started from the previous solution, and keeps its preconditioner
/// while it stays effective: it is recomputed when the pattern changes or when a solve
/// needed more than `refresh_iterations` Krylov iterations.
/// Defaults: CG preconditioned by a sparse Cholesky factorisation (nested-dissection
/// ordering), rtol 1e-10. PETSc options with prefix "cd0_" override them, e.g.
/// -cd0_pc_type icc, -cd0_pc_type jacobi, -cd0_ksp_rtol 1e-8.
class PetscContactSolver final : public ContactSolver {
  public:
    /// `options`: extra PETSc options (e.g. "-cd0_pc_type icc"), inserted into the options
    /// database before the KSP reads it.
    PetscContactSolver(std::size_t n, double delta, const std::string& options = "");
    ~PetscContactSolver() override;
    PetscContactSolver(const PetscContactSolver&) = delete;
    PetscContactSolver& operator=(const PetscContactSolver&) = delete;

    SolveInfo solve(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                    std::size_t pattern_version, std::span<const double> b_x,
                    std::span<const double> b_y, std::span<double> u_x,
                    std::span<double> u_y) override;

    /// Iterations above which the preconditioner is recomputed for the next solve.
    static constexpr int refresh_iterations = 2;

  private:
    struct Impl;
    Impl* impl_;
};

} // namespace jamsim::linalg
