#pragma once
#include <memory>

#include "jamsim/linalg/contact_solver.hpp"

namespace jamsim::linalg {

/// The CD0 contact matrix solved with CHOLMOD (SuiteSparse, PETSc's own sparse direct package
/// in Debian) as a simplicial LDLᵀ factor that is modified in place as contacts form and break:
///  - the symbolic analysis (fill-reducing ordering: METIS nested dissection by default, AMD
///    on request) is done on the candidate pairs' pattern, so every pair that may touch
///    before the next candidate list lies in the factor's pattern; at a new list it is carried
///    over by relabelling its rows (CholmodUpdatedFactor::adopt);
///  - a step's contact changes (contacts that formed: A + w wᵀ, that broke: A − w wᵀ) are
///    applied in place in one pass along the union of their elimination-tree paths (the method
///    of CHOLMOD's cholmod_updown, Davis and Hager, up to 63 changes per pass); a contact that
///    formed outside the factor's pattern goes through cholmod_updown, which adds the fill;
///  - each solve is one pass of triangular solves for both right-hand sides (x and y share
///    the matrix: A u_x = b_x, A u_y = b_y);
///  - after changes the true residual ‖b − A u‖ ≤ rtol ‖b‖ is checked for both right-hand
///    sides, and the factor is recomputed from scratch when round-off accumulated by the
///    changes makes it miss.
/// The factor itself (analysis, updates, solves) is CholmodUpdatedFactor, shared with the
/// PETSc backend's default preconditioner. Below φ_J the contact graph falls apart into
/// clusters, but the factor's pattern is the candidates', which stays connected: an
/// update walks the whole elimination-tree path of its rows (measured costs: tests/bench/cd0_solver.md).
/// Everything is sequential and deterministic (no threads, fixed ordering seed).
class CholmodContactSolver final : public ContactSolver {
  public:
    enum class Ordering { metis, amd };
    CholmodContactSolver(std::size_t n, double delta, Ordering ordering = Ordering::metis, double rtol = 1e-10);
    ~CholmodContactSolver() override;
    CholmodContactSolver(const CholmodContactSolver&) = delete;
    CholmodContactSolver& operator=(const CholmodContactSolver&) = delete;

    SolveInfo solve(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                    std::size_t pattern_version, std::span<const std::int32_t> labels, std::span<const double> b_x,
                    std::span<const double> b_y, std::span<double> u_x, std::span<double> u_y) override;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace jamsim::linalg
