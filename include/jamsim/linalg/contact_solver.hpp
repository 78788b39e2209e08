#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace jamsim::linalg {

/// One candidate pair of the CD0 contact matrix (a neighbour-list pair).
struct ContactPair {
    std::int32_t i, j;
};

/// Outcome of one solve, for diagnostics and failure messages.
struct SolveInfo {
    int iterations_x = 0, iterations_y = 0;
    bool refactored = false;  // the preconditioner / factor was recomputed for this solve
    int factor_updates = 0;   // rank-one updates/downdates applied to the factor (Eigen)
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
class ContactSolver {
  public:
    /// `options`: extra PETSc options (e.g. "-cd0_pc_type icc"), inserted into the options
    /// database before the KSP reads it.
    ContactSolver(std::size_t n, double delta, const std::string& options = "");
    ~ContactSolver();
    ContactSolver(const ContactSolver&) = delete;
    ContactSolver& operator=(const ContactSolver&) = delete;

    /// Solve A u_x = b_x and A u_y = b_y; u_x, u_y hold the initial guess on entry.
    /// `pairs` are the candidate pairs, `in_contact[k]` says whether pair k touches now;
    /// `pattern_version` changes whenever `pairs` changes (the list's build count).
    /// Throws std::runtime_error naming the KSP converged reason when a solve diverges.
    SolveInfo solve(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                    std::size_t pattern_version, std::span<const double> b_x,
                    std::span<const double> b_y, std::span<double> u_x, std::span<double> u_y);

    /// Iterations above which the preconditioner is recomputed for the next solve.
    static constexpr int refresh_iterations = 2;

  private:
    struct Impl;
    Impl* impl_;
};

} // namespace jamsim::linalg
