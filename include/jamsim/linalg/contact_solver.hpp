#pragma once
#include <cstdint>
#include <memory>
#include <string_view>
#include <span>
#include <string>
#include <vector>

namespace jamsim::linalg {

/// One candidate pair of the CD0 contact matrix: a pair that may touch before the candidate
/// list changes (the CD0 model passes its SubList of the neighbour list).
struct ContactPair {
    std::int32_t i, j;
};

/// Whether ‖b − A u‖ ≤ rtol ‖b‖ for both right-hand sides, with (A u)_i = δ u_i +
/// Σ_{j in contact} (u_i − u_j): the true-residual check of the backends that update a factor.
/// `scratch` holds the residual (resized to 2N: (x, y) per disk on one thread; all x, then all
/// y, when two threads take one component each).
bool contact_residual_within(std::span<const double> bx, std::span<const double> by, std::span<const double> ux,
                             std::span<const double> uy, double delta, std::span<const ContactPair> contacts,
                             double rtol, std::vector<double>& scratch);

/// Outcome of one solve, for diagnostics and failure messages.
struct SolveInfo {
    int iterations_x = 0, iterations_y = 0;
    bool refactored = false;  // the preconditioner / factor was recomputed for this solve
    int factor_updates = 0;   // rank-one updates/downdates applied to the factor
    bool relabelled = false;  // a new candidate list: the factor was carried over (relabelled)
    // Wall-clock seconds in the updated CHOLMOD factor (petsc and cholmod backends) during
    // this solve: keeping it equal to the matrix (updates, factorisations) and applying it;
    // of the upkeep, the part in a factorisation from scratch (serial).
    double factor_upkeep_seconds = 0, factor_solve_seconds = 0, factor_fresh_seconds = 0;
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

/// The CD0 contact matrix A (thesis eq. 4.15): A_ii = z_i + δ, A_ij = −1 per contact. One
/// interface, three backends: PetscContactSolver (KSP; by default preconditioned by the
/// updated CHOLMOD factor), CholmodContactSolver (that factor alone) and EigenContactSolver (Eigen LDLᵀ updated in place);
/// make_contact_solver picks one. The x and y systems share A (the drag is isotropic per
/// contact, eqs. 4.17-4.18), so every backend factors once and solves both.
class ContactSolver {
  public:
    virtual ~ContactSolver() = default;
    /// Solve A u_x = b_x and A u_y = b_y; u_x, u_y hold the initial guess on entry.
    /// `pairs` are the candidate pairs, `in_contact[k]` says whether pair k touches now;
    /// `pattern_version` changes whenever `pairs` changes (the candidate list's build count).
    /// `labels[i]` is row i's lasting identity (the disk's tag, a permutation of 0 … n−1):
    /// rows are renumbered when the disks are re-sorted at a neighbour-list rebuild, and a
    /// backend that keeps a factor carries it over by relabelling instead of factorising anew.
    /// Throws std::runtime_error naming the reason when a solve fails.
    virtual SolveInfo solve(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                            std::size_t pattern_version, std::span<const std::int32_t> labels,
                            std::span<const double> b_x, std::span<const double> b_y, std::span<double> u_x,
                            std::span<double> u_y) = 0;
};

/// The backend `solver = "auto"` picks: PETSc KSP with its default preconditioner, the
/// CHOLMOD LDLᵀ factor updated in place (PetscContactSolver), at every N. The "cholmod"
/// backend is the same factor without PETSc (its own residual check), "eigen" an Eigen LDLᵀ
/// updated by rank-one changes; jamsim_bench_cd0 compares them (tests/bench/cd0_solver.md).
inline constexpr std::string_view resolve_backend(std::string_view backend, std::size_t /*n*/) {
    return backend == "auto" ? std::string_view("petsc") : backend;
}

/// The options prefix of the CD0 solver's KSP and PC: every PETSc option given to CD0 must
/// carry it ("-cd0_pc_type icc"); an unprefixed one would configure nothing of CD0.
inline constexpr std::string_view kPetscPrefix = "cd0_";

/// The option names of a PETSc options string, as PETSc splits it: whitespace-separated
/// tokens that start with '-' and are not numbers ("-cd0_pc_type icc -cd0_ksp_rtol 1e-8"
/// -> {"-cd0_pc_type", "-cd0_ksp_rtol"}). Needs no PETSc.
std::vector<std::string> petsc_option_names(const std::string& options);

/// "" when PETSc accepts `options` and the CD0 solver's KSP uses every one of them, else what
/// is wrong ("-cd0_pc_typo is not used by the CD0 solver", or PETSc's own error). Checked by
/// a PetscContactSolver on the contact matrix of two disks, solved twice (touching, apart) (output of view or monitor options discarded); the options database is left as it
/// was. Initialises PETSc when needed (PetscScope finalises it).
std::string petsc_options_problem(const std::string& options);

/// "" unless PETSc's own sources of options (the PETSC_OPTIONS environment variable, an
/// options file it reads) set an option of the CD0 solver (prefix -cd0_), else one sentence
/// naming it: such an option changes CD0's results (iterations, tolerances) while the archive
/// records none, and a resume or a shard without it mixed two solvers in one archive.
/// Initialises PETSc when needed (PetscScope finalises it).
std::string petsc_environment_problem();

/// The backend for `n` disks: "auto", "cholmod", "petsc" or "eigen" (the `solver` parameter;
/// also "cholmod-amd", CHOLMOD with AMD ordering, for benchmarks); `petsc_options` go to the
/// PETSc backend. Throws std::invalid_argument for another name.
std::unique_ptr<ContactSolver> make_contact_solver(std::string_view backend, std::size_t n, double delta,
                                                   const std::string& petsc_options);

}  // namespace jamsim::linalg
