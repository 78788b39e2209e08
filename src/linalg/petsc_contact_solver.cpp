#include "jamsim/linalg/petsc_contact_solver.hpp"

#include <petscksp.h>

#include <algorithm>
#include <span>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "cholmod_factor.hpp"
#include "petsc_support.hpp"

namespace jamsim::linalg {

using petsc::check;

struct PetscContactSolver::Impl {
    PetscInt n = 0;  // disks: the KSP's system has 2n unknowns, u_x then u_y
    double delta = 0, rtol = 0;
    Mat A = nullptr;  // diag(A_c, A_c), A_c the n × n contact matrix: SeqAIJ, or
                      // with the default PC a MATSHELL over the current contacts
    Vec b = nullptr, x = nullptr;
    KSP ksp = nullptr;
    bool shell = false;  // the PC is the default one: the CHOLMOD factor below
    std::unique_ptr<CholmodUpdatedFactor> factor;
    std::string apply_error;            // an exception caught in the PC's apply, for the message
    std::vector<std::string> inserted;  // options this solver put into PETSc's database
    KSPNormType norm_type = KSP_NORM_UNPRECONDITIONED;

    std::size_t version = static_cast<std::size_t>(-1);  // pattern the Mat was built for
    std::vector<std::uint8_t> assembled;                 // contact set the Mat holds
    std::vector<int> contacts_of;                        // per disk: contacts in `assembled`
    // Positions in the SeqAIJ value array (rows sorted by column), first half; the second
    // half's are `half` further on.
    std::vector<PetscInt> diag_slot, slot_ij, slot_ji;
    PetscInt half = 0;
    bool factor_exact = false;     // the factor solves the Mat to round-off (fresh or verified)
    double half_rtol = 0;          // the KSP's rtol (default or -cd0_ksp_rtol): each half's bound
    std::vector<double> residual;  // scratch of the residual check
    bool refresh = true;           // factorise afresh (shell) / recompute the PC (others) next
    KSPConvergedReason last_reason = KSP_CONVERGED_ITERATING;  // of the last KSPSolve

    /// The default PC's apply, z = A⁻¹ r: one pass of the factor for both halves.
    static PetscErrorCode apply(PC pc, Vec r, Vec z) {
        void* ctx = nullptr;
        PetscErrorCode rc = PCShellGetContext(pc, &ctx);
        if (rc) return rc;
        auto* m = static_cast<Impl*>(ctx);
        const PetscScalar* in = nullptr;
        PetscScalar* out = nullptr;
        if ((rc = VecGetArrayRead(r, &in))) return rc;
        if ((rc = VecGetArrayWrite(z, &out))) return rc;
        try {
            m->factor->solve(in, out);
        } catch (const std::exception& e) { m->apply_error = e.what(); }
        if ((rc = VecRestoreArrayWrite(z, &out))) return rc;
        if ((rc = VecRestoreArrayRead(r, &in))) return rc;
        return m->apply_error.empty() ? PetscErrorCode(0) : PetscErrorCode(PETSC_ERR_LIB);
    }

    void configure(const std::string& prefix) {
        check(KSPCreate(PETSC_COMM_SELF, &ksp), "KSPCreate");
        check(KSPSetOptionsPrefix(ksp, prefix.c_str()), "KSPSetOptionsPrefix");
        // Defaults: iterative refinement (Richardson) preconditioned by the updated factor.
        check(KSPSetType(ksp, KSPRICHARDSON), "KSPSetType");
        PC pc;
        check(KSPGetPC(ksp, &pc), "KSPGetPC");
        check(PCSetType(pc, PCSHELL), "PCSetType");
        check(PCShellSetApply(pc, &Impl::apply), "PCShellSetApply");
        check(PCShellSetContext(pc, this), "PCShellSetContext");
        check(PCShellSetName(pc, "CD0 contact matrix: CHOLMOD LDL^T updated as contacts change"), "PCShellSetName");
        // Converge on the true residual of the scaled system (each half of b has unit norm):
        // ‖r‖ ≤ rtol/√2 ‖b‖ gives ‖b_x − A u_x‖ ≤ rtol ‖b_x‖ and the same for y.
        check(KSPSetTolerances(ksp, rtol, 1e-30, PETSC_DEFAULT, 10000), "KSPSetTolerances");
        check(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
        check(KSPSetFromOptions(ksp), "KSPSetFromOptions");  // options win
        // rtol (default or -cd0_ksp_rtol) bounds each half: the joint test takes rtol/√2.
        PetscReal given = 0;
        check(KSPGetTolerances(ksp, &given, nullptr, nullptr, nullptr), "KSPGetTolerances");
        // Checked here, as given: PETSc would refuse rtol >= 1 only below, naming rtol/√2;
        // below 1e-16 (about half the double epsilon) round-off alone keeps the KSP from converging.
        if (!(given >= 1e-16 && given < 1.0)) {
            char text[160];
            std::snprintf(text, sizeof text,
                          "-%sksp_rtol from 1e-16 to below 1, relative to each half of the right-hand side (it "
                          "is %g)",
                          prefix.c_str(), static_cast<double>(given));
            throw std::invalid_argument(text);
        }
        half_rtol = given;
        check(KSPSetTolerances(ksp, given / std::sqrt(2.0), PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT),
              "KSPSetTolerances");
        check(KSPGetPC(ksp, &pc), "KSPGetPC");
        PetscBool is_shell = PETSC_FALSE;
        check(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCSHELL, &is_shell), "PetscObjectTypeCompare");
        shell = is_shell;
        if (shell) {
            factor = std::make_unique<CholmodUpdatedFactor>(static_cast<std::size_t>(n), delta,
                                                            CholmodUpdatedFactor::Ordering::metis);
        } else {
            // Another PC (PETSc's own Cholesky, ICC, hypre, ...) is kept while it needs few
            // iterations: CG (unless a KSP was named), warm-started from the last velocities.
            PetscBool named = PETSC_FALSE;
            check(PetscOptionsHasName(nullptr, prefix.c_str(), "-ksp_type", &named), "PetscOptionsHasName");
            if (!named) check(KSPSetType(ksp, KSPCG), "KSPSetType");
            check(KSPSetInitialGuessNonzero(ksp, PETSC_TRUE), "KSPSetInitialGuessNonzero");
        }
        check(KSPGetNormType(ksp, &norm_type), "KSPGetNormType");
    }

    /// y = diag(A_c, A_c) x from the factor's current contact list (the default PC's Mat: the
    /// factor needs no assembled matrix, and the contacts are fewer than the candidate pairs).
    static PetscErrorCode mult(Mat a, Vec in, Vec out) {
        void* ctx = nullptr;
        PetscErrorCode rc = MatShellGetContext(a, &ctx);
        if (rc) return rc;
        const auto* m = static_cast<const Impl*>(ctx);
        const PetscScalar* x = nullptr;
        PetscScalar* y = nullptr;
        if ((rc = VecGetArrayRead(in, &x))) return rc;
        if ((rc = VecGetArrayWrite(out, &y))) return rc;
        const auto nn = static_cast<std::size_t>(m->n);
        for (std::size_t i = 0; i < 2 * nn; ++i) y[i] = m->delta * x[i];
        for (const ContactPair& c : m->factor->contacts()) {
            const auto i = static_cast<std::size_t>(c.i), j = static_cast<std::size_t>(c.j);
            const double dx = x[i] - x[j], dy = x[nn + i] - x[nn + j];
            y[i] += dx;
            y[j] -= dx;
            y[nn + i] += dy;
            y[nn + j] -= dy;
        }
        if ((rc = VecRestoreArrayWrite(out, &y))) return rc;
        return VecRestoreArrayRead(in, &x);
    }

    /// The default PC's operator: a MATSHELL (made once; it reads the factor's contacts).
    void make_shell_operator() {
        check(MatCreateShell(PETSC_COMM_SELF, 2 * n, 2 * n, 2 * n, 2 * n, this, &A), "MatCreateShell");
        check(MatShellSetOperation(A, MATOP_MULT, reinterpret_cast<void (*)(void)>(&Impl::mult)),
              "MatShellSetOperation");
        check(KSPSetOperators(ksp, A, A), "KSPSetOperators");
    }

    /// The 2n × 2n SeqAIJ pattern: the diagonal and every candidate pair in each half.
    void build_pattern(std::span<const ContactPair> pairs) {
        const auto nn = static_cast<std::size_t>(n);
        std::vector<std::vector<std::pair<PetscInt, std::int64_t>>> rows(nn);  // (column, what)
        for (std::size_t r = 0; r < nn; ++r) rows[r].emplace_back(static_cast<PetscInt>(r), -1);
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            const auto i = static_cast<std::size_t>(pairs[k].i), j = static_cast<std::size_t>(pairs[k].j);
            rows[i].emplace_back(pairs[k].j, static_cast<std::int64_t>(2 * k));
            rows[j].emplace_back(pairs[k].i, static_cast<std::int64_t>(2 * k + 1));
        }
        std::vector<PetscInt> start(2 * nn + 1, 0), cols;
        diag_slot.assign(nn, 0);
        slot_ij.assign(pairs.size(), 0);
        slot_ji.assign(pairs.size(), 0);
        for (std::size_t r = 0; r < nn; ++r) {
            std::sort(rows[r].begin(), rows[r].end());
            for (const auto& [col, what] : rows[r]) {
                const auto at = static_cast<PetscInt>(cols.size());
                if (what < 0)
                    diag_slot[r] = at;
                else
                    (what % 2 == 0 ? slot_ij : slot_ji)[static_cast<std::size_t>(what / 2)] = at;
                cols.push_back(col);
            }
            start[r + 1] = static_cast<PetscInt>(cols.size());
        }
        half = static_cast<PetscInt>(cols.size());
        for (std::size_t r = 0; r < nn; ++r) {
            for (PetscInt s = start[r]; s < start[r + 1]; ++s) cols.push_back(cols[static_cast<std::size_t>(s)] + n);
            start[nn + r + 1] = static_cast<PetscInt>(cols.size());
        }
        const std::vector<PetscScalar> zeros(cols.size(), 0.0);
        if (A) check(MatDestroy(&A), "MatDestroy");
        check(MatCreate(PETSC_COMM_SELF, &A), "MatCreate");
        check(MatSetSizes(A, 2 * n, 2 * n, 2 * n, 2 * n), "MatSetSizes");
        check(MatSetType(A, MATSEQAIJ), "MatSetType");
        // Explicit zeros for pairs not touching: the pattern holds every candidate pair.
        check(MatSeqAIJSetPreallocationCSR(A, start.data(), cols.data(), zeros.data()), "MatSeqAIJSetPreallocationCSR");
        check(KSPSetOperators(ksp, A, A), "KSPSetOperators");
        assembled.assign(pairs.size(), 0);
        contacts_of.assign(nn, 0);
        write_values(pairs, {}, true);
        refresh = true;
    }

    /// Writes the Mat's values for `in_contact` (all of them when `all`, else the pairs that
    /// changed); returns the number of pairs that changed.
    int write_values(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact, bool all) {
        PetscScalar* v = nullptr;
        int changes = 0;
        check(MatSeqAIJGetArray(A, &v), "MatSeqAIJGetArray");
        auto set = [&](PetscInt s, double value) {
            v[s] = value;
            v[s + half] = value;
        };
        if (all) {
            for (std::size_t r = 0; r < diag_slot.size(); ++r) set(diag_slot[r], delta + contacts_of[r]);
        } else {
            for (std::size_t k = 0; k < pairs.size(); ++k) {
                if (in_contact[k] == assembled[k]) continue;
                ++changes;
                assembled[k] = in_contact[k];
                const int d = in_contact[k] ? 1 : -1;
                const auto i = static_cast<std::size_t>(pairs[k].i), j = static_cast<std::size_t>(pairs[k].j);
                contacts_of[i] += d;
                contacts_of[j] += d;
                set(slot_ij[k], in_contact[k] ? -1.0 : 0.0);
                set(slot_ji[k], in_contact[k] ? -1.0 : 0.0);
                // Integers plus δ, recomputed (not accumulated) so that no round-off drifts.
                set(diag_slot[i], delta + contacts_of[i]);
                set(diag_slot[j], delta + contacts_of[j]);
            }
        }
        check(MatSeqAIJRestoreArray(A, &v), "MatSeqAIJRestoreArray");
        // (Restoring the array raises the Mat's state: a PETSc preconditioner sees the change.)
        return changes;
    }

    /// One KSPSolve of the scaled system; returns its iterations, or −1 when it diverged.
    PetscInt run_ksp() {
        apply_error.clear();
        const PetscErrorCode rc = KSPSolve(ksp, b, x);
        if (rc != 0) {
            std::string text = petsc::error_text(rc);
            if (!apply_error.empty()) text += ": " + apply_error;
            throw std::runtime_error("PETSc: KSPSolve failed: " + text);
        }
        KSPConvergedReason reason;
        check(KSPGetConvergedReason(ksp, &reason), "KSPGetConvergedReason");
        PetscInt its = 0;
        check(KSPGetIterationNumber(ksp, &its), "KSPGetIterationNumber");
        last_reason = reason;
        return reason < 0 ? -1 : its;
    }
    /// The backend's solve (PetscContactSolver::solve adds the factor's timings).
    /// Brings the preconditioner to the current contacts: the updated CHOLMOD factor (carried
    /// over a new candidate list, updated by the contacts' changes, or factorised afresh when
    /// `refresh` asks), or PETSc's own, recomputed when the pattern or `refresh` asks.
    /// With `shortcut_rhs` (b_x, b_y, u_x, u_y: the shortcut below will follow), the factor's
    /// update and its application to b go together (CholmodUpdatedFactor::follow_and_solve,
    /// the same bits), and `solved` says so.
    struct Rhs {
        std::span<const double> b_x, b_y;
        std::span<double> u_x, u_y;
    };
    SolveInfo update_preconditioner(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                                    std::size_t pattern_version, std::span<const std::int32_t> labels,
                                    const Rhs* shortcut_rhs, bool& solved);
    SolveInfo run(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                  std::size_t pattern_version, std::span<const std::int32_t> labels, std::span<const double> b_x,
                  std::span<const double> b_y, std::span<double> u_x, std::span<double> u_y);
};

PetscContactSolver::PetscContactSolver(std::size_t n, double delta, const std::string& options, double rtol)
    : impl_(new Impl{}) {
    try {
        petsc::ensure_initialized();
        if (!options.empty()) {
            check(PetscOptionsInsertString(nullptr, options.c_str()), "PetscOptionsInsertString");
            impl_->inserted = petsc_option_names(options);
        }
        impl_->n = static_cast<PetscInt>(n);
        impl_->delta = delta;
        impl_->rtol = rtol;
        check(VecCreateSeq(PETSC_COMM_SELF, 2 * impl_->n, &impl_->b), "VecCreateSeq");
        check(VecDuplicate(impl_->b, &impl_->x), "VecDuplicate");
        impl_->configure(std::string(kPetscPrefix));
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
    // Options are read until the factor is set up (MUMPS reads its own then): they stay in
    // the database while the solver lives and no longer, so the next solver starts clean.
    for (const auto& name : impl_->inserted) PetscOptionsClearValue(nullptr, name.c_str());
    delete impl_;
    impl_ = nullptr;
}

SolveInfo PetscContactSolver::solve(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                                    std::size_t pattern_version, std::span<const std::int32_t> labels,
                                    std::span<const double> b_x, std::span<const double> b_y, std::span<double> u_x,
                                    std::span<double> u_y) {
    Impl& m = *impl_;
    return with_factor_timings(m.factor.get(),
                               [&] { return m.run(pairs, in_contact, pattern_version, labels, b_x, b_y, u_x, u_y); });
}

SolveInfo PetscContactSolver::Impl::update_preconditioner(std::span<const ContactPair> pairs,
                                                          std::span<const std::uint8_t> in_contact,
                                                          std::size_t pattern_version,
                                                          std::span<const std::int32_t> labels, const Rhs* shortcut_rhs,
                                                          bool& solved) {
    Impl& m = *this;
    SolveInfo info;
    solved = false;
    if (m.shell) {
        if (!m.A) m.make_shell_operator();
        if (pattern_version != m.version) {
            info.relabelled = m.factor->adopt(pairs, labels);
            m.version = pattern_version;
        }
        if (m.refresh || !m.factor->has_factor()) {
            m.factor->factorize(pairs, in_contact);
            m.factor_exact = true;
            m.refresh = false;
            info.refactored = true;
        } else {
            if (shortcut_rhs) {
                info.factor_updates =
                    m.factor->follow_and_solve(pairs, in_contact, shortcut_rhs->b_x.data(), shortcut_rhs->b_y.data(),
                                               shortcut_rhs->u_x.data(), shortcut_rhs->u_y.data());
                solved = true;
            } else {
                info.factor_updates = m.factor->follow(pairs, in_contact);
            }
            if (info.factor_updates > 0 || info.relabelled) m.factor_exact = false;
        }
    } else {
        (void)labels;  // PETSc's own preconditioners are recomputed with the pattern
        if (pattern_version != m.version) {
            m.build_pattern(pairs);
            m.version = pattern_version;
        }
        const int changes = m.write_values(pairs, in_contact, false);
        if (changes > 0 || m.refresh) {
            check(KSPSetReusePreconditioner(m.ksp, m.refresh ? PETSC_FALSE : PETSC_TRUE), "KSPSetReusePreconditioner");
            info.refactored = m.refresh;
            m.refresh = false;
        }
    }
    return info;
}

SolveInfo PetscContactSolver::Impl::run(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                                        std::size_t pattern_version, std::span<const std::int32_t> labels,
                                        std::span<const double> b_x, std::span<const double> b_y, std::span<double> u_x,
                                        std::span<double> u_y) {
    Impl& m = *this;
    const auto nn = static_cast<std::size_t>(m.n);
    // Whenever the shell's factor is updated, the shortcut applies it next (a norm is checked).
    const Rhs rhs{b_x, b_y, u_x, u_y};
    bool solved = false;
    SolveInfo info = m.update_preconditioner(pairs, in_contact, pattern_version, labels,
                                             m.shell && m.norm_type != KSP_NORM_NONE ? &rhs : nullptr, solved);
    // The default PC after contact changes: one application of the updated factor, whose
    // true residual is checked here for each half in one pass (as the cholmod backend does);
    // only when it misses the tolerance does the KSP refine, from that solution.
    const bool check_here = m.shell && !m.factor_exact && m.norm_type != KSP_NORM_NONE;
    const bool shortcut = m.shell && (m.factor_exact || check_here) && m.norm_type != KSP_NORM_NONE;
    if (solved && !shortcut) throw std::logic_error("CD0 PETSc solver: the factor applied for a solve that refines");
    // A KSP solves the system with each right-hand side scaled to unit norm, so that its
    // joint convergence test bounds each half; one application of the factor (the shortcut)
    // needs no scaling, and its result is then the cholmod backend's, bit for bit.
    double sx = 1.0, sy = 1.0;
    bool scaled = false;
    const auto scale_system = [&](bool with_guess) {
        scaled = true;
        double norm_x = 0, norm_y = 0;
        for (std::size_t i = 0; i < nn; ++i) {
            norm_x += b_x[i] * b_x[i];
            norm_y += b_y[i] * b_y[i];
        }
        sx = norm_x > 0 ? 1 / std::sqrt(norm_x) : 1.0;  // a zero half stays zero
        sy = norm_y > 0 ? 1 / std::sqrt(norm_y) : 1.0;
        PetscScalar* pb = nullptr;
        check(VecGetArrayWrite(m.b, &pb), "VecGetArrayWrite");
        for (std::size_t i = 0; i < nn; ++i) {
            pb[i] = b_x[i] * sx;
            pb[nn + i] = b_y[i] * sy;
        }
        check(VecRestoreArrayWrite(m.b, &pb), "VecRestoreArrayWrite");
        if (!with_guess) return;  // the guess, read by a KSP with a nonzero initial guess
        PetscScalar* px = nullptr;
        check(VecGetArrayWrite(m.x, &px), "VecGetArrayWrite");
        for (std::size_t i = 0; i < nn; ++i) {
            px[i] = u_x[i] * sx;
            px[nn + i] = u_y[i] * sy;
        }
        check(VecRestoreArrayWrite(m.x, &px), "VecRestoreArrayWrite");
    };
    // The shortcut: the factor is exact for this very matrix (or its residual is checked
    // next), so any KSP would return the PC's application after one iteration; the shell's
    // factor is applied alone, on the caller's arrays (no norms, no KSP set-up, no copies
    // into PETSc's Vecs): the same bits as one Richardson step from a zero guess.
    PetscInt its = 1;
    if (shortcut) {
        if (!solved) m.factor->solve(b_x.data(), b_y.data(), u_x.data(), u_y.data());
        m.last_reason = KSP_CONVERGED_ITS;
    } else {
        scale_system(true);
        its = m.run_ksp();
    }
    if (check_here &&
        !contact_residual_within(b_x, b_y, u_x, u_y, m.delta, m.factor->contacts(), m.half_rtol, m.residual)) {
        // Refinement by the KSP from the factor's solution, scaled.
        scale_system(true);
        check(KSPSetInitialGuessNonzero(m.ksp, PETSC_TRUE), "KSPSetInitialGuessNonzero");
        const PetscInt more = m.run_ksp();
        check(KSPSetInitialGuessNonzero(m.ksp, PETSC_FALSE), "KSPSetInitialGuessNonzero");
        its = more < 0 ? -1 : std::max<PetscInt>(2, more + 1);
    }
    // (A negative count comes from a KSP, so the system is scaled by now.)
    if (its < 0 && m.shell && !info.refactored) {  // round-off of many updates: start afresh
        m.factor->factorize(pairs, in_contact);
        info.refactored = true;
        check(VecSet(m.x, 0.0), "VecSet");
        its = m.run_ksp();
    }
    if (its < 0) {
        char tolerance[32];
        std::snprintf(tolerance, sizeof tolerance, "%.3g", static_cast<double>(m.half_rtol));
        PetscInt most = 0;
        check(KSPGetTolerances(m.ksp, nullptr, nullptr, nullptr, &most), "KSPGetTolerances");
        const std::string why =
            m.last_reason == KSP_DIVERGED_ITS
                ? " (the iteration limit, " + std::to_string(most) +
                      " iterations, came before the relative tolerance " + tolerance +
                      " for each half: raise -cd0_ksp_max_it, loosen -cd0_ksp_rtol, or use a preconditioner that "
                      "suits the contact matrix)"
                : std::string(" (relative tolerance ") + tolerance +
                      " for each half; a tighter one than round-off allows, or a solver that does not suit the "
                      "contact matrix?)";
        throw std::runtime_error(std::string("CD0 contact solve did not converge: ") +
                                 KSPConvergedReasons[m.last_reason] + why);
    }
    if (m.shell && (!shortcut || check_here)) {
        // One application met the tolerance: the updated factor is exact for this matrix.
        // More: round-off accumulated by the updates; factorise afresh next time.
        m.factor_exact = its <= 1;
        m.refresh = its > 1;
    } else if (!m.shell && its > PetscContactSolver::refresh_iterations) {
        m.refresh = true;
    }
    info.iterations_x = info.iterations_y = static_cast<int>(its);
    if (!scaled) return info;  // the shortcut's solution is in (u_x, u_y) already
    const PetscScalar* px = nullptr;
    check(VecGetArrayRead(m.x, &px), "VecGetArrayRead");
    for (std::size_t i = 0; i < nn; ++i) {
        u_x[i] = px[i] / sx;
        u_y[i] = px[nn + i] / sy;
    }
    check(VecRestoreArrayRead(m.x, &px), "VecRestoreArrayRead");
    return info;
}

}  // namespace jamsim::linalg
