#include "jamsim/linalg/petsc_contact_solver.hpp"
#include "jamsim/linalg/eigen_contact_solver.hpp"
#include "jamsim/linalg/cholmod_contact_solver.hpp"

#include <petscksp.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace jamsim::linalg {

namespace {

/// Every PETSc call goes through here: a non-zero code becomes an exception (PETSc's own
/// handler is replaced by PetscReturnErrorHandler, so nothing aborts the MPI job).
std::string petsc_error_text(PetscErrorCode rc);

void check(PetscErrorCode rc, const char* what) {
    if (rc == 0) return;
    throw std::runtime_error(std::string("PETSc: ") + what + " failed: " + petsc_error_text(rc));
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

/// The CD0 solver's KSP configuration, options last (so that they win): both the solver and
/// the options check use it.
void configure_ksp(KSP ksp) {
    check(KSPSetOptionsPrefix(ksp, std::string(kPetscPrefix).c_str()), "KSPSetOptionsPrefix");
    check(KSPSetType(ksp, KSPCG), "KSPSetType");
    PC pc;
    check(KSPGetPC(ksp, &pc), "KSPGetPC");
    check(PCSetType(pc, PCCHOLESKY), "PCSetType");
    check(PCFactorSetMatOrderingType(pc, MATORDERINGND), "PCFactorSetMatOrderingType");
    check(KSPSetTolerances(ksp, 1e-10, 1e-30, PETSC_DEFAULT, 10000), "KSPSetTolerances");
    check(KSPSetInitialGuessNonzero(ksp, PETSC_TRUE), "KSPSetInitialGuessNonzero");
    // Converge on the true residual ‖b − A u‖ ≤ rtol ‖b‖ (units of velocity), not the
    // preconditioned one, whose meaning changes with a stale preconditioner.
    check(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
    check(KSPSetFromOptions(ksp), "KSPSetFromOptions");  // last: options win
}

/// PETSc objects of the options check, destroyed in any case (errors there cannot be
/// reported from a destructor and change nothing of the check's answer).
struct CheckObjects {
    KSP ksp = nullptr;
    Mat a = nullptr;
    Vec b = nullptr, x = nullptr;
    CheckObjects() = default;
    CheckObjects(const CheckObjects&) = delete;
    CheckObjects& operator=(const CheckObjects&) = delete;
    ~CheckObjects() {
        if (ksp) KSPDestroy(&ksp);
        if (a) MatDestroy(&a);
        if (b) VecDestroy(&b);
        if (x) VecDestroy(&x);
    }
};

/// Removes the checked options from the database again, whatever happens.
struct ClearOptions {
    const std::vector<std::string>& names;
    explicit ClearOptions(const std::vector<std::string>& n) : names(n) {}
    ClearOptions(const ClearOptions&) = delete;
    ClearOptions& operator=(const ClearOptions&) = delete;
    ~ClearOptions() {
        for (const auto& name : names) PetscOptionsClearValue(nullptr, name.c_str());
    }
};

/// Standard output sent to /dev/null while it lives (view and monitor options of the tiny
/// check solve print there); restored, flushed, on destruction.
class SilencedStdout {
  public:
    SilencedStdout() {
        std::fflush(stdout);
        saved_ = ::dup(STDOUT_FILENO);
        if (saved_ < 0) throw std::runtime_error("PETSc options check: dup(stdout) failed");
        const int null = ::open("/dev/null", O_WRONLY);
        if (null < 0 || ::dup2(null, STDOUT_FILENO) < 0) {
            if (null >= 0) ::close(null);
            ::close(saved_);
            throw std::runtime_error("PETSc options check: cannot redirect stdout");
        }
        ::close(null);
    }
    ~SilencedStdout() {
        std::fflush(stdout);
        ::dup2(saved_, STDOUT_FILENO);
        ::close(saved_);
    }
    SilencedStdout(const SilencedStdout&) = delete;
    SilencedStdout& operator=(const SilencedStdout&) = delete;

  private:
    int saved_ = -1;
};

/// PETSc's text for an error code and its last detailed message.
std::string petsc_error_text(PetscErrorCode rc) {
    const char* text = nullptr;
    char* specific = nullptr;
    PetscErrorMessage(rc, &text, &specific);
    std::string out = text ? text : "error";
    if (specific && *specific) out += std::string(" (") + specific + ")";
    return out;
}

} // namespace

std::vector<std::string> petsc_option_names(const std::string& options) {
    std::vector<std::string> names;
    std::istringstream in(options);
    for (std::string token; in >> token;) {
        if (token.size() < 2 || token[0] != '-') continue;  // a value
        const char c = token[1];
        if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') continue;  // -1, -.5
        names.push_back(token);
    }
    return names;
}

std::string petsc_options_problem(const std::string& options) {
    const std::vector<std::string> names = petsc_option_names(options);
    if (names.empty()) return "";
    ensure_petsc();
    for (const auto& name : names) {  // given before (not by a check): not ours to judge
        PetscBool set = PETSC_FALSE;
        check(PetscOptionsHasName(nullptr, nullptr, name.c_str(), &set), "PetscOptionsHasName");
        if (set) return name + " is already set in PETSc's options database";
    }
    const ClearOptions clear{names};
    CheckObjects o;
    try {
        check(PetscOptionsInsertString(nullptr, options.c_str()), "PetscOptionsInsertString");
        // The contact matrix of two touching disks with δ = 1e-3, solved once as CD0 would.
        check(MatCreateSeqAIJ(PETSC_COMM_SELF, 2, 2, 2, nullptr, &o.a), "MatCreateSeqAIJ");
        const PetscInt rows[] = {0, 1};
        const PetscScalar values[] = {1.001, -1.0, -1.0, 1.001};
        check(MatSetValues(o.a, 2, rows, 2, rows, values, INSERT_VALUES), "MatSetValues");
        check(MatAssemblyBegin(o.a, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
        check(MatAssemblyEnd(o.a, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
        check(VecCreateSeq(PETSC_COMM_SELF, 2, &o.b), "VecCreateSeq");
        check(VecDuplicate(o.b, &o.x), "VecDuplicate");
        check(VecSet(o.b, 1.0), "VecSet");
        check(VecSet(o.x, 0.0), "VecSet");
        check(KSPCreate(PETSC_COMM_SELF, &o.ksp), "KSPCreate");
        const SilencedStdout quiet;
        configure_ksp(o.ksp);
        check(KSPSetOperators(o.ksp, o.a, o.a), "KSPSetOperators");
        check(KSPSolve(o.ksp, o.b, o.x), "KSPSolve");
    } catch (const std::runtime_error& e) {
        return std::string("options PETSc accepts: ") + e.what();
    }
    for (const auto& name : names) {
        PetscBool used = PETSC_FALSE;
        // The database keeps names without their leading dash.
        check(PetscOptionsUsed(nullptr, name.c_str() + 1, &used), "PetscOptionsUsed");
        if (!used) return name + " is not used by the CD0 solver (PETSc KSP and PC with prefix -" +
                          std::string(kPetscPrefix) + "; e.g. -cd0_ksp_type, -cd0_pc_type, -cd0_ksp_rtol)";
    }
    return "";
}

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
        configure_ksp(impl_->ksp);
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
    backend = resolve_backend(backend, n);
    if (backend == "eigen") return std::make_unique<EigenContactSolver>(n, delta);
    if (backend == "cholmod")
        return std::make_unique<CholmodContactSolver>(n, delta);
    if (backend == "cholmod-amd")  // the ordering compared in jamsim_bench_cd0
        return std::make_unique<CholmodContactSolver>(n, delta, CholmodContactSolver::Ordering::amd);
    if (backend == "petsc")
        return std::make_unique<PetscContactSolver>(n, delta, petsc_options);
    throw std::invalid_argument("unknown CD0 solver '" + std::string(backend) +
                                "' (known: auto, cholmod, petsc, eigen)");
}

bool contact_residual_within(std::span<const double> bx, std::span<const double> by,
                             std::span<const double> ux, std::span<const double> uy, double delta,
                             std::span<const ContactPair> contacts, double rtol,
                             std::vector<double>& rx, std::vector<double>& ry) {
    const std::size_t size = bx.size();
    rx.resize(size);
    ry.resize(size);
    for (std::size_t i = 0; i < size; ++i) {
        rx[i] = bx[i] - delta * ux[i];
        ry[i] = by[i] - delta * uy[i];
    }
    for (const auto& c : contacts) {
        const auto i = static_cast<std::size_t>(c.i), j = static_cast<std::size_t>(c.j);
        const double dx = ux[i] - ux[j], dy = uy[i] - uy[j];
        rx[i] -= dx;
        rx[j] += dx;
        ry[i] -= dy;
        ry[j] += dy;
    }
    double r2x = 0, r2y = 0, b2x = 0, b2y = 0;
    for (std::size_t i = 0; i < size; ++i) {
        r2x += rx[i] * rx[i];
        r2y += ry[i] * ry[i];
        b2x += bx[i] * bx[i];
        b2y += by[i] * by[i];
    }
    const double tol2 = rtol * rtol;
    return r2x <= tol2 * b2x && r2y <= tol2 * b2y;
}

} // namespace jamsim::linalg
