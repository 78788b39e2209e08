#pragma once
#include <string>

#include "jamsim/linalg/contact_solver.hpp"

namespace jamsim::linalg {

/// Solves the CD0 contact matrix (thesis eq. 4.15: A_ii = z_i + δ, A_ij = −1 per contact) with
/// PETSc KSP on PETSC_COMM_SELF (each rank runs its own replicas).
///
/// The KSP solves both right-hand sides at once, as one system of 2n unknowns with the matrix
/// diag(A, A) (SeqAIJ), each half of the right-hand side scaled to unit norm. The Mat has the
/// pattern of the *candidate pairs* (every pair that may touch before the next list, explicit
/// zeros for pairs not touching); a step writes only the entries of contacts that formed or
/// broke, in place.
///
/// Default (no options): Richardson iteration (iterative refinement) preconditioned by a
/// PCSHELL that applies a CHOLMOD LDLᵀ factor of A (METIS ordering of the candidates'
/// pattern) kept equal to A by multiple-rank updates and downdates as contacts change
/// (CholmodUpdatedFactor). After changes the factor is applied once (PCApply) and the true
/// residual ‖b − A u‖ ≤ rtol ‖b‖ checked for u_x and u_y in one pass (rtol = 1e-10, the KSP's
/// rtol); where round-off of the updates left more, the KSP refines from that solution and
/// the factor is made afresh for the next solve.
/// While the contacts and so A are unchanged since a factor was verified (or made), a solve is
/// one application of the factor.
///
/// PETSc options with prefix "cd0_" override this: e.g. -cd0_ksp_rtol 1e-12, -cd0_ksp_type cg,
/// or another preconditioner (-cd0_pc_type cholesky / icc / hypre / gamg, with
/// -cd0_pc_factor_mat_solver_type cholmod / mumps / superlu ...), which is then used with CG
/// (unless -cd0_ksp_type names another KSP), warm-started from the last velocities, and kept
/// until a solve needs more than `refresh_iterations` iterations.
class PetscContactSolver final : public ContactSolver {
  public:
    /// `options`: extra PETSc options (e.g. "-cd0_ksp_rtol 1e-12"), inserted into the options
    /// database before the KSP reads it.
    PetscContactSolver(std::size_t n, double delta, const std::string& options = "", double rtol = 1e-10);
    ~PetscContactSolver() override;
    PetscContactSolver(const PetscContactSolver&) = delete;
    PetscContactSolver& operator=(const PetscContactSolver&) = delete;

    SolveInfo solve(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                    std::size_t pattern_version, std::span<const std::int32_t> labels, std::span<const double> b_x,
                    std::span<const double> b_y, std::span<double> u_x, std::span<double> u_y) override;

    /// With a PETSc preconditioner other than the default: iterations above which it is
    /// recomputed for the next solve.
    static constexpr int refresh_iterations = 2;

  private:
    struct Impl;
    Impl* impl_;
};

}  // namespace jamsim::linalg
