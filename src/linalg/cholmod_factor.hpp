#pragma once
// The CD0 contact matrix's LDLᵀ factor in CHOLMOD, kept equal to the matrix of the current
// contact set by multiple-rank updates: the one factor behind both the "cholmod" backend and
// the PETSc backend's default preconditioner (a PCSHELL around it).
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "jamsim/linalg/contact_solver.hpp"

namespace jamsim::linalg {

/// A_ii = z_i + δ, A_ij = −1 per contact, as a simplicial LDLᵀ factor:
///  - a fresh factor orders (METIS nested dissection, or AMD) the pattern of every candidate
///    pair (explicit zeros for pairs not touching), so no contact that forms before the next
///    candidate list needs new fill;
///  - `factorize` computes the numeric factor of a contact set from scratch;
///  - `adopt` carries the factor over a new candidate list (rows renumbered by the re-sorting
///    of the disks; contacts formed later may then add fill, which CHOLMOD's update makes);
///  - `follow` brings the factor to a new contact set: each contact that formed is a rank-one
///    update A + w wᵀ, each that broke a downdate, w = e_i − e_j. They are applied in place,
///    all of a step's changes in one pass along the union of their elimination-tree paths
///    (`sweep`, the method of CHOLMOD's cholmod_updown, Davis and Hager, with every change of a
///    column applied while the column is in cache, and the dense separators at the top of the
///    tree, where every path ends, in SIMD loops); a contact outside L's pattern, possible
///    after `adopt`, goes through cholmod_updown, which allocates the fill;
///  - `solve` applies A⁻¹ to both right-hand sides (n × 2, column major) in one pass over L
///    for both.
/// Deterministic (fixed ordering), and the same bits on any number of threads. On two threads
/// or more (n of at least kThreadedLoopMin) the elimination tree is split into two groups of
/// subtrees and the top above them (Impl::split_tree): `follow` sweeps the groups side by side,
/// `solve` and `follow_and_solve` also split their passes over L along it. Every entry gets the
/// operations of one thread in the same order. (Without a split, `solve` takes the x and y
/// halves side by side.)
class CholmodUpdatedFactor {
  public:
    enum class Ordering { metis, amd };
    /// The vectors of the update's kernels for consecutive rows: `best` takes AVX-512 or AVX2
    /// where the processor has them, `avx2` at most AVX2, `sse2` the x86-64 baseline. All
    /// give the same bits (no contraction into FMAs, element-wise operations): the narrower
    /// ones are there to test that.
    enum class Vectors { best, avx2, sse2 };
    CholmodUpdatedFactor(std::size_t n, double delta, Ordering ordering, Vectors vectors = Vectors::best);
    ~CholmodUpdatedFactor();
    CholmodUpdatedFactor(const CholmodUpdatedFactor&) = delete;
    CholmodUpdatedFactor& operator=(const CholmodUpdatedFactor&) = delete;

    /// A new candidate list (the rows may be renumbered, `labels` gives each
    /// row's lasting identity). The factor is carried over when it can be: the elimination
    /// order stays that of the same disks, so L is unchanged and only the permutation is
    /// renumbered; contacts of the factor missing from `pairs` are downdated. Carried over
    /// while the fill (entries of L, grown by updates) stays below kFillGrowth times that of
    /// the last fresh factor; else, and without a factor, the next `factorize` orders and
    /// analyses `pairs` afresh. Returns whether the factor was carried over.
    bool adopt(std::span<const ContactPair> pairs, std::span<const std::int32_t> labels);
    /// Numeric factor of the contact set `in_contact` (one flag per pair of the last `adopt`),
    /// ordering and analysing the candidate pattern first when the factor's analysis is of an
    /// earlier list.
    void factorize(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact);
    /// Updates the factor to `in_contact`; returns the number of contacts formed or broken.
    int follow(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact);
    /// `follow`, then `solve`, with the same bits: the sweep's last pass and the solve run as
    /// one step (cholmod_solve.cpp), the forward pass right behind the sweep (reading each
    /// column it changed while in the cache); on two threads or more (n of at least
    /// kThreadedLoopMin) split along the elimination tree, each thread's passes over L
    /// starting as soon as the columns they read are final (the update and each pass read
    /// most of L, 22 MB at N = 65536).
    int follow_and_solve(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                         const double* b_x, const double* b_y, double* u_x, double* u_y);
    /// (u_x, u_y) = A⁻¹ (b_x, b_y), each of n; no input may overlap an output.
    void solve(const double* b_x, const double* b_y, double* u_x, double* u_y);
    /// x = A⁻¹ b for b, x of n × 2 (x half then y half).
    void solve(const double* b, double* x);

    bool has_factor() const;
    /// The vectors the update's consecutive-row kernels run on: "avx512f", "avx2" or "sse2".
    const char* vector_kernels() const;
    /// Entries of L over those of the last fresh factor at which `adopt` analyses afresh
    /// (downdates keep their entries, and the order ages as the disks move apart). Low: a
    /// contact that forms across a separator of the old order fills its whole path, and the
    /// steps' cost grows faster than the entries (N = 65536, φ = 0.84: 8 → 15 ms a step on one
    /// thread as the fill reaches 1.4). With 1.02 a 4000-step run's CD0 step cost 8–30% less on
    /// one thread and 36–43% less on two than with 1.3, the fresh analyses (0.45 s each, every
    /// 500–700 steps) included (tests/bench/cd0_threads.md, "CD0 over long runs").
    static constexpr double kFillGrowth = 1.02;
    /// What `follow` did since construction: changes applied by the in-place sweep, contacts
    /// formed outside L's pattern (CHOLMOD's update, which allocates their fill), and fresh
    /// factorisations after a downdate met a pivot that was not positive.
    /// Also the wall-clock seconds spent keeping the factor (factorize, adopt, follow) and in
    /// its solves, for benchmarks (follow_and_solve's solve, which runs inside its sweep's last
    /// pass, counts as keeping).
    /// `block_updates`: entry updates (entries × changes) made by the consecutive-row kernels
    /// on whole blocks of rows, the part that `Vectors` selects.
    /// `split_solves`: solves on two threads (split along the tree, or x and y side by side);
    /// `split_steps`: follow_and_solve calls whose sweep and solve ran split along the tree.
    /// `fresh_seconds`: the part of the upkeep spent in `factorize` (a numeric factor from
    /// scratch, with the ordering and analysis when the candidate list is new).
    struct Counts {
        long swept = 0, filled = 0, refactored = 0, block_updates = 0, split_solves = 0, split_steps = 0;
        double upkeep_seconds = 0, solve_seconds = 0, fresh_seconds = 0;
    };
    Counts counts() const;
    /// The contacts of the last `factorize` or `follow` (residual check, matrix products).
    std::span<const ContactPair> contacts() const;

  private:
    /// Orders (METIS nested dissection, or AMD) and analyses the candidate pattern.
    void analyse(std::span<const ContactPair> pairs);
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// `run()` (a backend's solve, returning SolveInfo) with the time it spent in `factor` (which
/// may be null) added to its SolveInfo.
template <class Run> SolveInfo with_factor_timings(const CholmodUpdatedFactor* factor, Run&& run) {
    const auto before = factor ? factor->counts() : CholmodUpdatedFactor::Counts{};
    SolveInfo info = run();
    if (factor) {
        const auto after = factor->counts();
        info.factor_upkeep_seconds = after.upkeep_seconds - before.upkeep_seconds;
        info.factor_solve_seconds = after.solve_seconds - before.solve_seconds;
        info.factor_fresh_seconds = after.fresh_seconds - before.fresh_seconds;
        if (after.refactored > before.refactored) info.refactored = true;  // a failed downdate's fresh factor
    }
    return info;
}

}  // namespace jamsim::linalg
