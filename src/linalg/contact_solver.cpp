#include "jamsim/linalg/petsc_contact_solver.hpp"
#include "jamsim/linalg/eigen_contact_solver.hpp"
#include "jamsim/linalg/cholmod_contact_solver.hpp"

#include <petscsys.h>

#include "petsc_support.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include <omp.h>

#include "jamsim/parallel/threads.hpp"

namespace jamsim::linalg {

using petsc::check;

namespace {

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

}  // namespace

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
    // PETSc reads "-name [value] -name [value] ...": a word where neither fits was dropped
    // without a word ("cd0_ksp_type gmres" set nothing), and a tab joined two words into one name.
    if (options.find_first_of("\t\n\r\v\f") != std::string::npos)
        return "options separated by spaces (it holds a tab or a line break)";
    {
        std::istringstream in(options);
        bool value_allowed = false;  // right after an option's name
        for (std::string token; in >> token;) {
            const bool name = token.size() >= 2 && token[0] == '-' &&
                              !std::isdigit(static_cast<unsigned char>(token[1])) && token[1] != '.';
            if (!name && !value_allowed)
                return "'" + token + "' is neither an option's name (-" + std::string(kPetscPrefix) +
                       "...) nor the value of the one before it (each takes one value at most)";
            value_allowed = name;
        }
    }
    const std::vector<std::string> names = petsc_option_names(options);
    if (names.empty()) return "";
    petsc::ensure_initialized();
    for (const auto& name : names) {  // given before (not by a check): not ours to judge
        PetscBool set = PETSC_FALSE;
        check(PetscOptionsHasName(nullptr, nullptr, name.c_str(), &set), "PetscOptionsHasName");
        if (set) return name + " is already set in PETSc's options database";
    }
    const ClearOptions clear{names};
    try {
        check(PetscOptionsInsertString(nullptr, options.c_str()), "PetscOptionsInsertString");
        // The very solver CD0 uses, on the contact matrix of two touching disks (δ = 1e-3),
        // solved once as CD0 would: a first step (fresh factor) and one after the contact broke.
        const SilencedStdout quiet;
        PetscContactSolver solver(2, 1e-3);
        const ContactPair pair[] = {{0, 1}};
        const std::uint8_t touching[] = {1}, apart[] = {0};
        const std::int32_t labels[] = {0, 1};
        const double bx[] = {1.0, -1.0}, by[] = {0.5, -0.5};
        double ux[] = {0.0, 0.0}, uy[] = {0.0, 0.0};
        solver.solve(pair, touching, 0, labels, bx, by, ux, uy);
        solver.solve(pair, apart, 0, labels, bx, by, ux, uy);
    } catch (const std::invalid_argument& e) {  // a value jamsim itself refuses: the message says which
        return e.what();
    } catch (const std::runtime_error& e) { return std::string("options PETSc accepts: ") + e.what(); }
    for (const auto& name : names) {
        PetscBool used = PETSC_FALSE;
        // The database keeps names without their leading dash.
        check(PetscOptionsUsed(nullptr, name.c_str() + 1, &used), "PetscOptionsUsed");
        if (!used)
            return name + " is not used by the CD0 solver (PETSc KSP and PC with prefix -" + std::string(kPetscPrefix) +
                   "; e.g. -cd0_ksp_type, -cd0_pc_type, -cd0_ksp_rtol)";
    }
    return "";
}

std::string petsc_environment_problem() {
    petsc::ensure_initialized();
    char* all = nullptr;  // "-name value -name value ...", PETSc's copy
    check(PetscOptionsGetAll(nullptr, &all), "PetscOptionsGetAll");
    const std::string options = all ? all : "";
    PetscFree(all);
    std::string prefix(1, '-');  // appended, not '+': GCC 12's -Wrestrict misfires on that
    prefix.append(kPetscPrefix);
    for (const std::string& name : petsc_option_names(options))
        if (name.starts_with(prefix))
            return "PETSc's options (the PETSC_OPTIONS environment variable, or an options file PETSc reads) set " +
                   name +
                   ", an option of the CD0 solver, which changes CD0's results while the archive records "
                   "none of it: give the solver's options as [model] petsc_options (jamsim replica "
                   "--petsc-options), which the archive keeps, and leave them out of PETSc's own options";
    return "";
}

PetscScope::~PetscScope() {
    PetscBool up = PETSC_FALSE, down = PETSC_FALSE;
    PetscInitialized(&up);
    PetscFinalized(&down);
    if (up && !down) PetscFinalize();
}

std::unique_ptr<ContactSolver> make_contact_solver(std::string_view backend, std::size_t n, double delta,
                                                   const std::string& petsc_options) {
    backend = resolve_backend(backend, n);
    if (backend == "eigen") return std::make_unique<EigenContactSolver>(n, delta);
    if (backend == "cholmod") return std::make_unique<CholmodContactSolver>(n, delta);
    if (backend == "cholmod-amd")  // the ordering compared in jamsim_bench_cd0
        return std::make_unique<CholmodContactSolver>(n, delta, CholmodContactSolver::Ordering::amd);
    if (backend == "petsc") return std::make_unique<PetscContactSolver>(n, delta, petsc_options);
    throw std::invalid_argument("unknown CD0 solver '" + std::string(backend) +
                                "' (known: auto, cholmod, petsc, eigen)");
}

namespace {

/// One component of contact_residual_within, its sums in the same order as there (the same
/// bits): whether ‖b − A u‖ ≤ rtol ‖b‖; `r` holds N doubles of scratch.
bool component_residual_within(std::span<const double> b, std::span<const double> u, double delta,
                               std::span<const ContactPair> contacts, double rtol, double* r) {
    const std::size_t size = b.size();
    double b2 = 0;
    for (std::size_t i = 0; i < size; ++i) {
        r[i] = b[i] - delta * u[i];
        b2 += b[i] * b[i];
    }
    const double* const p = u.data();
    for (const auto& c : contacts) {
        const auto i = static_cast<std::size_t>(c.i), j = static_cast<std::size_t>(c.j);
        const double d = p[i] - p[j];
        r[i] -= d;
        r[j] += d;
    }
    double r2 = 0;
    for (std::size_t i = 0; i < size; ++i) r2 += r[i] * r[i];
    return r2 <= rtol * rtol * b2;
}

}  // namespace

bool contact_residual_within(std::span<const double> bx, std::span<const double> by, std::span<const double> ux,
                             std::span<const double> uy, double delta, std::span<const ContactPair> contacts,
                             double rtol, std::vector<double>& scratch) {
    // The residual of disk i as the pair (r_x, r_y) at scratch[2i]: a contact then updates
    // its two disks with one 16-byte load and store each, where separate x and y arrays took
    // two of each (the contacts' pass is most of the check). Every sum is taken in the same
    // order as with separate arrays, so the same bits.
    using Pair = double __attribute__((vector_size(16)));
    const std::size_t size = bx.size();
    scratch.resize(2 * size);
    if (size >= kThreadedLoopMin && kernel_threads() > 1) {
        // Two threads: x on one, y on the other, each component's sums in the order below.
        bool within[2] = {false, false};
        const TimedRegion timed;
#pragma omp parallel num_threads(2)
        {
            const int thread = omp_get_thread_num();
            const bool alone = omp_get_num_threads() == 1;  // a team of one takes both
            for (int axis = thread; axis < 2; axis += alone ? 1 : 2)
                within[axis] = axis == 0
                                   ? component_residual_within(bx, ux, delta, contacts, rtol, scratch.data())
                                   : component_residual_within(by, uy, delta, contacts, rtol, scratch.data() + size);
        }
        return within[0] && within[1];
    }
    double* const r = scratch.data();
    double b2x = 0, b2y = 0;
    for (std::size_t i = 0; i < size; ++i) {
        r[2 * i] = bx[i] - delta * ux[i];
        r[2 * i + 1] = by[i] - delta * uy[i];
        b2x += bx[i] * bx[i];
        b2y += by[i] * by[i];
    }
    const double* const px = ux.data();
    const double* const py = uy.data();
    for (const auto& c : contacts) {
        const auto i = static_cast<std::size_t>(c.i), j = static_cast<std::size_t>(c.j);
        const Pair d{px[i] - px[j], py[i] - py[j]};
        Pair ri, rj;
        std::memcpy(&ri, r + 2 * i, sizeof ri);
        ri -= d;
        std::memcpy(r + 2 * i, &ri, sizeof ri);
        std::memcpy(&rj, r + 2 * j, sizeof rj);
        rj += d;
        std::memcpy(r + 2 * j, &rj, sizeof rj);
    }
    Pair r2{0.0, 0.0};
    for (std::size_t i = 0; i < size; ++i) {
        Pair ri;
        std::memcpy(&ri, r + 2 * i, sizeof ri);
        r2 += ri * ri;
    }
    const double tol2 = rtol * rtol;
    return r2[0] <= tol2 * b2x && r2[1] <= tol2 * b2y;
}

}  // namespace jamsim::linalg
