#include "jamsim/linalg/petsc_contact_solver.hpp"
#include "jamsim/linalg/eigen_contact_solver.hpp"

#include <petscksp.h>

#include <algorithm>
#include <stdexcept>

namespace jamsim::linalg {

namespace {

/// Every PETSc call goes through here: a non-zero code becomes an exception (PETSc's own
/// handler is replaced by PetscReturnErrorHandler, so nothing aborts the MPI job).
void check(PetscErrorCode rc, const char* what) {
    if (rc == 0) return;
    const char* text = nullptr;
    PetscErrorMessage(rc, &text, nullptr);
    throw std::runtime_error(std::string("PETSc: ") + what + " failed: " + (text ? text : "?"));
}

void ensure_petsc() {
    PetscBool up = PETSC_FALSE;
    check(PetscInitialized(&up), "PetscInitialized");
    if (up) return;
    // Each rank solves its own replicas and initialises PETSc when it first needs it, at a
    // time no other rank shares: PETSc's world must then be this process alone.
    // (Only when MPI is already running; otherwise PETSc starts it for this process alone.)
    int mpi_up = 0;
    MPI_Initialized(&mpi_up);
    if (mpi_up) PETSC_COMM_WORLD = MPI_COMM_SELF;
    check(PetscOptionsSetValue(nullptr, "-no_signal_handler", "true"), "PetscOptionsSetValue");
    check(PetscInitializeNoArguments(), "PetscInitialize");
    check(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr), "PetscPushErrorHandler");
}

} // namespace

PetscScope::~PetscScope() {
    PetscBool up = PETSC_FALSE, down = PETSC_FALSE;
    PetscInitialized(&up);
    PetscFinalized(&down);
    if (up && !down) PetscFinalize();
}

struct PetscContactSolver::Impl {
    PetscInt n;
    double delta;
    Mat A = nullptr;
    Vec b = nullptr, x = nullptr;
    KSP ksp = nullptr;
    std::size_t version = static_cast<std::size_t>(-1);  // pattern the Mat was built for
    bool refresh_pc = true;
    bool refreshed = false;  // the preconditioner is recomputed in this solve
    std::vector<std::uint8_t> assembled;  // contact set the Mat holds now
    // CSR over the candidate pairs (diagonal first); slot[k] = positions of pair k's two
    // off-diagonal entries, so values can be refilled without searching.
    std::vector<PetscInt> start, cols;
    std::vector<PetscScalar> vals;
    std::vector<std::size_t> slot_ij, slot_ji;

    void build_pattern(std::span<const ContactPair> pairs) {
        std::vector<PetscInt> degree(static_cast<std::size_t>(n), 0);
        for (const auto& c : pairs) {
            ++degree[static_cast<std::size_t>(c.i)];
            ++degree[static_cast<std::size_t>(c.j)];
        }
        start.assign(static_cast<std::size_t>(n) + 1, 0);
        for (std::size_t r = 0; r < static_cast<std::size_t>(n); ++r)
            start[r + 1] = start[r] + 1 + degree[r];
        cols.assign(static_cast<std::size_t>(start.back()), 0);
        vals.assign(cols.size(), 0.0);
        std::vector<PetscInt> fill(start.begin(), start.end() - 1);
        for (PetscInt r = 0; r < n; ++r) cols[static_cast<std::size_t>(fill[static_cast<std::size_t>(r)]++)] = r;
        slot_ij.resize(pairs.size());
        slot_ji.resize(pairs.size());
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            const auto i = static_cast<std::size_t>(pairs[k].i), j = static_cast<std::size_t>(pairs[k].j);
            slot_ij[k] = static_cast<std::size_t>(fill[i]++);
            cols[slot_ij[k]] = pairs[k].j;
            slot_ji[k] = static_cast<std::size_t>(fill[j]++);
            cols[slot_ji[k]] = pairs[k].i;
        }
        if (A) check(MatDestroy(&A), "MatDestroy");
        std::vector<PetscInt> nnz(static_cast<std::size_t>(n));
        for (std::size_t r = 0; r < nnz.size(); ++r) nnz[r] = start[r + 1] - start[r];
        check(MatCreateSeqAIJ(PETSC_COMM_SELF, n, n, 0, nnz.data(), &A), "MatCreateSeqAIJ");
        // Keep explicit zeros: the pattern must hold every candidate pair.
        check(MatSetOption(A, MAT_IGNORE_ZERO_ENTRIES, PETSC_FALSE), "MatSetOption");
        refresh_pc = true;
    }

    void assemble(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                  std::size_t pattern_version) {
        if (!A || pattern_version != version) {
            build_pattern(pairs);
            version = pattern_version;
            assembled.clear();
        }
        // The values depend only on the contact set: an unchanged set leaves the Mat (and its
        // state counter) alone, so an up-to-date preconditioner is kept as it is.
        if (!refresh_pc && std::equal(in_contact.begin(), in_contact.end(), assembled.begin(),
                                      assembled.end()))
            return;
        assembled.assign(in_contact.begin(), in_contact.end());
        for (PetscInt r = 0; r < n; ++r) vals[static_cast<std::size_t>(start[static_cast<std::size_t>(r)])] = delta;
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            const double v = in_contact[k] ? -1.0 : 0.0;
            vals[slot_ij[k]] = v;
            vals[slot_ji[k]] = v;
            vals[static_cast<std::size_t>(start[static_cast<std::size_t>(pairs[k].i)])] -= v;
            vals[static_cast<std::size_t>(start[static_cast<std::size_t>(pairs[k].j)])] -= v;
        }
        for (PetscInt r = 0; r < n; ++r) {
            const auto s0 = static_cast<std::size_t>(start[static_cast<std::size_t>(r)]);
            const auto m = start[static_cast<std::size_t>(r) + 1] - start[static_cast<std::size_t>(r)];
            check(MatSetValues(A, 1, &r, m, &cols[s0], &vals[s0], INSERT_VALUES), "MatSetValues");
        }
        check(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
        check(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
        check(KSPSetOperators(ksp, A, A), "KSPSetOperators");
        check(KSPSetReusePreconditioner(ksp, refresh_pc ? PETSC_FALSE : PETSC_TRUE),
              "KSPSetReusePreconditioner");
        refreshed = refresh_pc;
        refresh_pc = false;
    }

    int solve_one(std::span<const double> rhs, std::span<double> u, const char* which) {
        PetscScalar* p = nullptr;
        check(VecGetArray(b, &p), "VecGetArray");
        std::copy(rhs.begin(), rhs.end(), p);
        check(VecRestoreArray(b, &p), "VecRestoreArray");
        check(VecGetArray(x, &p), "VecGetArray");
        std::copy(u.begin(), u.end(), p);
        check(VecRestoreArray(x, &p), "VecRestoreArray");
        check(KSPSolve(ksp, b, x), "KSPSolve");
        KSPConvergedReason reason;
        check(KSPGetConvergedReason(ksp, &reason), "KSPGetConvergedReason");
        if (reason < 0)
            throw std::runtime_error(std::string("CD0 contact solve for u_") + which +
                                     " did not converge: " + KSPConvergedReasons[reason]);
        PetscInt its = 0;
        check(KSPGetIterationNumber(ksp, &its), "KSPGetIterationNumber");
        if (its > PetscContactSolver::refresh_iterations) refresh_pc = true;
        const PetscScalar* q = nullptr;
        check(VecGetArrayRead(x, &q), "VecGetArrayRead");
        std::copy(q, q + n, u.begin());
        check(VecRestoreArrayRead(x, &q), "VecRestoreArrayRead");
        return static_cast<int>(its);
    }
};

PetscContactSolver::PetscContactSolver(std::size_t n, double delta, const std::string& options)
    : impl_(new Impl{}) {
    try {
        ensure_petsc();
        if (!options.empty())
            check(PetscOptionsInsertString(nullptr, options.c_str()), "PetscOptionsInsertString");
        impl_->n = static_cast<PetscInt>(n);
        impl_->delta = delta;
        check(VecCreateSeq(PETSC_COMM_SELF, impl_->n, &impl_->b), "VecCreateSeq");
        check(VecDuplicate(impl_->b, &impl_->x), "VecDuplicate");
        check(KSPCreate(PETSC_COMM_SELF, &impl_->ksp), "KSPCreate");
        check(KSPSetOptionsPrefix(impl_->ksp, "cd0_"), "KSPSetOptionsPrefix");
        check(KSPSetType(impl_->ksp, KSPCG), "KSPSetType");
        PC pc;
        check(KSPGetPC(impl_->ksp, &pc), "KSPGetPC");
        check(PCSetType(pc, PCCHOLESKY), "PCSetType");
        check(PCFactorSetMatOrderingType(pc, MATORDERINGND), "PCFactorSetMatOrderingType");
        check(KSPSetTolerances(impl_->ksp, 1e-10, 1e-30, PETSC_DEFAULT, 10000),
              "KSPSetTolerances");
        check(KSPSetInitialGuessNonzero(impl_->ksp, PETSC_TRUE), "KSPSetInitialGuessNonzero");
        // Converge on the true residual ‖b − A u‖ ≤ rtol ‖b‖ (units of velocity), not the
        // preconditioned one, whose meaning changes with a stale preconditioner.
        check(KSPSetNormType(impl_->ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
        check(KSPSetFromOptions(impl_->ksp), "KSPSetFromOptions");  // last: options win
    } catch (...) {
        this->~PetscContactSolver();
        throw;
    }
}

PetscContactSolver::~PetscContactSolver() {
    if (!impl_) return;
    if (impl_->ksp) KSPDestroy(&impl_->ksp);
    if (impl_->A) MatDestroy(&impl_->A);
    if (impl_->b) VecDestroy(&impl_->b);
    if (impl_->x) VecDestroy(&impl_->x);
    delete impl_;
    impl_ = nullptr;
}

SolveInfo PetscContactSolver::solve(std::span<const ContactPair> pairs,
                               std::span<const std::uint8_t> in_contact,
                               std::size_t pattern_version, std::span<const double> b_x,
                               std::span<const double> b_y, std::span<double> u_x,
                               std::span<double> u_y) {
    impl_->refreshed = false;
    impl_->assemble(pairs, in_contact, pattern_version);
    SolveInfo info;
    info.refactored = impl_->refreshed;
    info.iterations_x = impl_->solve_one(b_x, u_x, "x");
    info.iterations_y = impl_->solve_one(b_y, u_y, "y");
    return info;
}

std::unique_ptr<ContactSolver> make_contact_solver(std::string_view backend, std::size_t n,
                                                   double delta,
                                                   const std::string& petsc_options) {
    if (backend == "eigen" || (backend == "auto" && n <= kAutoEigenMaxN))
        return std::make_unique<EigenContactSolver>(n, delta);
    if (backend == "petsc" || backend == "auto")
        return std::make_unique<PetscContactSolver>(n, delta, petsc_options);
    throw std::invalid_argument("unknown CD0 solver '" + std::string(backend) +
                                "' (known: auto, petsc, eigen)");
}

} // namespace jamsim::linalg
