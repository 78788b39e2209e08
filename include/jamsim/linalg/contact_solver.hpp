#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace jamsim::linalg {

/// One contact of the CD0 contact matrix (i < j not required).
struct ContactPair {
    std::int32_t i, j;
};

/// Outcome of one solve, for diagnostics and failure messages.
struct SolveInfo {
    int iterations_x = 0, iterations_y = 0;
};

/// PETSc is initialised on first use (on PETSC_COMM_SELF problems only) and finalised by
/// this scope object, which main() holds; tests that never create one simply leave PETSc
/// running until exit.
class PetscScope {
  public:
    PetscScope() = default;
    ~PetscScope();
    PetscScope(const PetscScope&) = delete;
    PetscScope& operator=(const PetscScope&) = delete;
};

/// Solves A u = b for the CD0 contact matrix A (thesis eq. 4.15): A_ii = z_i + δ,
/// A_ij = −1 per contact, with PETSc KSP on PETSC_COMM_SELF. The Mat (SeqAIJ) keeps its
/// sparsity pattern while the contact set stays the same (values refilled) and is rebuilt
/// when it changes; the KSP is reused and warm-started from the previous solution.
/// Defaults: CG + Jacobi, rtol 1e-10; PETSc options with prefix "cd0_" override them
/// (e.g. -cd0_ksp_type cg -cd0_pc_type icc -cd0_ksp_rtol 1e-8).
class ContactSolver {
  public:
    ContactSolver(std::size_t n, double delta);
    ~ContactSolver();
    ContactSolver(const ContactSolver&) = delete;
    ContactSolver& operator=(const ContactSolver&) = delete;

    /// Solve A u_x = b_x and A u_y = b_y; u_x, u_y hold the initial guess on entry.
    /// Throws std::runtime_error naming the KSP converged reason when a solve diverges.
    SolveInfo solve(std::span<const ContactPair> contacts, std::span<const double> b_x,
                    std::span<const double> b_y, std::span<double> u_x, std::span<double> u_y);

  private:
    struct Impl;
    Impl* impl_;
};

} // namespace jamsim::linalg
