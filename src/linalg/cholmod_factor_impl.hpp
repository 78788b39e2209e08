#pragma once
// The state of the updated CD0 factor (cholmod_factor.hpp), shared by its files: the factor
// and its bookkeeping (cholmod_factor.cpp), the sweep that applies a step's contact changes
// (cholmod_sweep.cpp) and the sweep's per-column kernels (SweepColumns, here). Internal to
// src/linalg.
#include <cholmod.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <span>
#include <string>
#include <stdexcept>
#include <utility>
#include <vector>

#include "cholmod_factor.hpp"
#include "cholmod_kernels.hpp"
#include "jamsim/parallel/threads.hpp"

namespace jamsim::linalg {

namespace factor_kernels {

/// Adds the wall-clock seconds of its scope to `total`, unless an enclosing one (which shares
/// `running`) already counts them.
class ScopeTimer {
  public:
    ScopeTimer(double& total, bool& running)
        : total_(running ? nullptr : &total), running_(running), start_(std::chrono::steady_clock::now()) {
        running_ = true;
    }
    ~ScopeTimer() {
        if (!total_) return;
        *total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        running_ = false;
    }
    ScopeTimer(const ScopeTimer&) = delete;
    ScopeTimer& operator=(const ScopeTimer&) = delete;

  private:
    double* total_;
    bool& running_;
    std::chrono::steady_clock::time_point start_;
};

/// The entry updates of the sweep's columns: a column's changes (their coefficients in
/// step_p, step_beta, step_w) on its entries.
struct SweepColumns {
    // The changes of one column (step_p, step_beta, step_w) applied to its entries l[0, len),
    // whose rows are given as places in the workspace: for each change in order,
    // w_r ← w_r − p l_r, then l_r ← l_r + β w_r. Runs of consecutive places go to the
    // consecutive-row kernels (`consecutive_kernel`, `consecutive2_kernel`, chosen by vector
    // width), the other entries kBlock at a time (independent chains the processor overlaps).
    static constexpr int kBlock = 8;
    static constexpr int kRank = 63;      // changes per sweep at most (bits of a 64-bit mask, less one)
    const char* vector_kernels = "sse2";  // the vectors of the kernels below
    ConsecutiveKernel consecutive_kernel = consecutive_sse2;
    Consecutive2Kernel consecutive2_kernel = consecutive2_sse2;
    double step_p[kRank], step_beta[kRank];
    double* step_w[kRank];
    // The second column of a pair (see `sweep`): its changes' coefficients.
    double step_p2[kRank], step_beta2[kRank];
    double* step_w2[kRank];
    long block_updates = 0;      // entry updates (entries × changes) by the consecutive-row kernels
    bool failed = false;         // a downdate met a pivot that was not positive
    std::vector<int> slot_rows;  // a column's rows as places in the workspace

    /// A column's `count` changes (step_p, step_beta, step_w) on its entries l[0, len), whose
    /// workspace rows are `rows`.
    void apply_column(double* l, const int* rows, int len, int count) {
        by_runs(
            rows, len,
            [&](int from, int to) {
                const int k = consecutive_kernel(ColumnChanges{step_p, step_beta, step_w}, l + from, rows[from],
                                                 to - from, count);
                block_updates += static_cast<long>(k) * count;
                return from + k;
            },
            [&](int from, int to) { apply_scattered(l + from, rows + from, to - from, count); });
    }

    /// The two columns of a pair on the same rows (the second column's coefficients in
    /// step_p2, step_beta2; the same changes): per entry and change, the first column's step
    /// before the second's, as column after column.
    void apply_pair(double* l1, double* l2, const int* rows, int len, int count) {
        by_runs(
            rows, len,
            [&](int from, int to) {
                const int k = consecutive2_kernel(ColumnChanges{step_p, step_beta, step_w},
                                                  ColumnChanges{step_p2, step_beta2, step_w}, l1 + from, l2 + from,
                                                  rows[from], to - from, count);
                block_updates += 2L * k * count;
                return from + k;
            },
            [&](int from, int to) { apply_scattered2(l1 + from, l2 + from, rows + from, to - from, count); });
    }

    /// A column's entries [0, len) split by their places in the workspace: runs of at least
    /// kMinRun consecutive places go to the consecutive-row kernel (`whole(from, to)`, which
    /// does whole blocks and returns where it stopped), everything else, the rest of a run
    /// included, to the scattered kernel (`scattered(from, to)`). Two thirds of the scattered
    /// columns' entry updates lie in such runs at N = 65536, φ = 0.80 (a lower separator's
    /// rows in its own chain and in the separators above it). Each entry gets the same
    /// operations in the same order whichever kernel takes it, so the same bits.
    static constexpr int kMinRun = 8;
    template <class Whole, class Scattered>
    static void by_runs(const int* rows, int len, Whole&& whole, Scattered&& scattered) {
        int rest = 0;                                         // entries from `rest` on are not done yet
        if (len > 0 && rows[len - 1] - rows[0] == len - 1) {  // one run (places ascend): no scan
            rest = len >= kMinRun ? whole(0, len) : 0;
            if (len > rest) scattered(rest, len);
            return;
        }
        for (int e = 0; e < len;) {
            int f = e + 1;
            while (f < len && rows[f] == rows[f - 1] + 1) ++f;
            if (f - e >= kMinRun) {
                if (e > rest) scattered(rest, e);
                rest = whole(e, f);
            }
            e = f;
        }
        if (len > rest) scattered(rest, len);
    }

    /// One entry (in workspace row `row`) alone.
    void apply_entry(double& entry, int row, int count) const {
        double v = entry;
        for (int s = 0; s < count; ++s) {
            double& wr = step_w[s][row];
            const double wk = wr - step_p[s] * v;
            wr = wk;
            v += step_beta[s] * wk;
        }
        entry = v;
    }

    void apply_scattered(double* l, const int* rows, int len, int count) const {
        int k = 0;
        for (; k + kBlock <= len; k += kBlock) {
            double v[kBlock];
            int r[kBlock];
            for (int u = 0; u < kBlock; ++u) {
                v[u] = l[k + u];
                r[u] = rows[k + u];
            }
            for (int s = 0; s < count; ++s) {
                double* wt = step_w[s];
                const double p = step_p[s], beta = step_beta[s];
                for (int u = 0; u < kBlock; ++u) {
                    const double wk = wt[r[u]] - p * v[u];
                    wt[r[u]] = wk;
                    v[u] += beta * wk;
                }
            }
            for (int u = 0; u < kBlock; ++u) l[k + u] = v[u];
        }
        for (; k < len; ++k) apply_entry(l[k], rows[k], count);
    }

    // Two columns of a pair over the same rows, each with its own coefficients (step_p,
    // step_beta; step_p2, step_beta2) and the same changes (step_w): per workspace entry and
    // change, the first column's step before the second's, as column after column.
    void apply_entry2(double& e1, double& e2, int row, int count) const {
        double v1 = e1, v2 = e2;
        for (int s = 0; s < count; ++s) {
            double& wr = step_w[s][row];
            double wk = wr - step_p[s] * v1;
            v1 += step_beta[s] * wk;
            wk = wk - step_p2[s] * v2;
            wr = wk;
            v2 += step_beta2[s] * wk;
        }
        e1 = v1;
        e2 = v2;
    }

    void apply_scattered2(double* l1, double* l2, const int* rows, int len, int count) const {
        constexpr int kRows = 4;
        int k = 0;
        for (; k + kRows <= len; k += kRows) {
            double v1[kRows], v2[kRows];
            int r[kRows];
            for (int u = 0; u < kRows; ++u) {
                v1[u] = l1[k + u];
                v2[u] = l2[k + u];
                r[u] = rows[k + u];
            }
            for (int s = 0; s < count; ++s) {
                double* wt = step_w[s];
                const double p1 = step_p[s], beta1 = step_beta[s], p2 = step_p2[s], beta2 = step_beta2[s];
                for (int u = 0; u < kRows; ++u) {
                    double wk = wt[r[u]] - p1 * v1[u];
                    v1[u] += beta1 * wk;
                    wk = wk - p2 * v2[u];
                    wt[r[u]] = wk;
                    v2[u] += beta2 * wk;
                }
            }
            for (int u = 0; u < kRows; ++u) {
                l1[k + u] = v1[u];
                l2[k + u] = v2[u];
            }
        }
        for (; k < len; ++k) apply_entry2(l1[k], l2[k], rows[k], count);
    }
};

/// A column of the second group with rows in the top (split_tree): its entries in the top's
/// rows, [first, end) (split_step's tails).
struct SplitTail {
    int column, first, end;
};

}  // namespace factor_kernels

/// L's column arrays, read-only (simplicial: column j's entries at [Lp[j], Lp[j] + Lnz[j]), the
/// diagonal first, rows ascending), for `const auto [Lp, Li, Lnz, Lx] = columns_of(L)`.
struct ColumnArrays {
    const int* p;
    const int* i;
    const int* nz;
    const double* x;
};
inline ColumnArrays columns_of(const cholmod_factor& L) {
    return {static_cast<const int*>(L.p), static_cast<const int*>(L.i), static_cast<const int*>(L.nz),
            static_cast<const double*>(L.x)};
}

/// The forward pass L z = y in place (y: the two right-hand sides as (x, y) pairs, rows of
/// L), column by column as far as asked: the sweep runs it right behind itself
/// (sweep_group), so that a column it has just changed is read again while in the cache
/// (the sweep's union of paths holds about 44% of L's entries at N = 65536). Columns in
/// ascending order, so every row of y takes its updates in the order of one pass: the same
/// operations and bits.
struct ForwardPass {
    const cholmod_factor& L;
    double* y;
    int next = 0;  ///< the first column not yet done
    /// Columns whose entries from `first` on are left out (split_step's second group: its
    /// entries in the top's rows wait for the first group's), ascending; those done dropped.
    std::span<const factor_kernels::SplitTail> tails = {};
    /// Impl::nests_next of L's current pattern, or null: two columns of a supernode taken
    /// together.
    const std::uint8_t* nests = nullptr;
    /// Columns [next, column) done.
    void run_to(int column);
};

/// Whether the factor's loops over n rows take two threads (the split sweep and solves).
inline bool two_threads(int n) { return kernel_threads() > 1 && static_cast<std::size_t>(n) >= kThreadedLoopMin; }

struct CholmodUpdatedFactor::Impl {
    using ScopeTimer = factor_kernels::ScopeTimer;
    int n = 0;
    double delta = 0;
    cholmod_common c{};
    cholmod_sparse* A = nullptr;  // lower triangle (stype −1), pattern = candidate pairs
    cholmod_factor* L = nullptr;
    std::vector<int> diag_slot, pair_slot;  // positions in A->x
    std::vector<int> pinv;                  // pinv[i] = row of L holding original row i
    bool analysis_current = false;          // A and the analysis are of the current pairs
    std::vector<std::int32_t> labels;       // labels of the rows at the last factorize/adopt
    double fresh_fill = 0;                  // entries of L after the last fresh factor
    std::vector<int> scratch;

    double fill() const {
        const auto* nz = static_cast<const int*>(L->nz);
        double total = 0;
        for (int j = 0; j < n; ++j) total += nz[j];
        return total;
    }
    std::vector<std::uint8_t> factored;  // contact set the factor represents
    std::vector<double> xy;              // solve: the permuted right-hand sides, interleaved
    // Workspace of `sweep`: one column per change over the rows of the union of the changes'
    // elimination-tree paths, that union, and per column of L which changes pass through it.
    std::vector<double> w;
    std::vector<std::uint64_t> on_path;
    static constexpr std::uint64_t kVisited = std::uint64_t{1} << 63;
    std::vector<int> path_union;
    std::vector<std::uint64_t> union_bits;  // sweep: the union as a bitmap of columns (zero between sweeps)
    Counts counts;
    bool timing = false;  // a ScopeTimer is counting
    bool have_factor = false;
    // The contacts of the last factorize(), adopt() or follow(): the first n_contacts entries
    // (follow() writes all pairs' slots without a branch, so the storage is as long as them).
    std::vector<ContactPair> contacts;
    std::size_t n_contacts = 0;
    std::vector<std::size_t> formed, broken, outside;
    std::vector<std::size_t> formed_second, broken_second;  // gather_changes' second thread's
    std::vector<std::pair<int, int>> sweep_rows;

    void fail(const char* what) const {
        throw std::runtime_error(std::string("CD0 CHOLMOD factor: ") + what + " failed (status " +
                                 std::to_string(c.status) + ")");
    }

    /// Rows (of L) a < b of a pair's change e_a − e_b, and whether L's pattern already has
    /// entry (b, a): then the change's path is the etree path from a (through b) and makes
    /// no fill, so `sweep` can apply it in place.
    bool fits(const ContactPair& pair, int& a, int& b) const {
        a = pinv[static_cast<std::size_t>(pair.i)];
        b = pinv[static_cast<std::size_t>(pair.j)];
        if (a > b) std::swap(a, b);
        const auto [Lp, Li, Lnz, Lx] = columns_of(*L);
        const int* first = Li + Lp[a] + 1;
        const int* last = Li + Lp[a] + Lnz[a];
        return std::binary_search(first, last, b);  // CHOLMOD keeps columns sorted
    }

    /// LDLᵀ ← LDLᵀ + Σ_t σ_t w_t w_tᵀ, w_t = e_{a_t} − e_{b_t} (rows of L; the pattern must
    /// already hold each (b_t, a_t), see `fits`), σ_t = +1 for t < n_up, −1 after: the rank-1
    /// modifications in sequence (method C1 of Gill, Golub, Murray and Saunders, as CHOLMOD
    /// uses) interleaved in one pass over the union of their elimination-tree paths, column by
    /// column (a column's ancestors come later), up to kSweepRank at a time (bit 63 of a
    /// column's mask marks the union). A column's runs of consecutive rows (all of a dense
    /// separator's at the top of the tree, where every path ends, and most of the others')
    /// run as contiguous vector loops (`by_runs`). Two columns of a supernode (the second's
    /// rows are the first's after its first) take their changes together, row by row, so
    /// that each workspace entry is loaded and stored once for both (the same bits as
    /// column after column). Sets columns.failed when a downdate meets a pivot that is not
    /// positive (the caller refactors).
    static constexpr int kSweepRank = factor_kernels::SweepColumns::kRank;
    /// On two threads (split_usable), each pass's two groups side by side (run_pass).
    void sweep(std::span<const std::pair<int, int>> rows, std::size_t n_up);
    /// One pass of the sweep (changes [start, start + kSweepRank) of `rows`): the union of
    /// their paths, the workspace, the union's places by column group (group_slots), each
    /// change's α set to ±1. On two threads (split_usable) the groups 0 and 1 of a pass can
    /// run side by side (each change's α is then written by its own group's thread; see
    /// take_alpha), and the top after both.
    struct Pass {
        std::size_t start = 0;
        int rank = 0;           // changes in the pass
        std::size_t slots = 0;  // rows of the workspace
    };
    Pass plan_pass(std::span<const std::pair<int, int>> rows, std::size_t n_up, std::size_t start, double* alpha);
    /// A planned pass: on two threads the groups side by side, then the top.
    void run_pass(const Pass& pass, std::span<const std::pair<int, int>> rows, double* alpha);
    /// The pass's columns of `group` (its workspace places, ascending) with the coefficient
    /// arrays of `cols` (one per thread); with `forward`, the forward pass run up to each
    /// column before it is swept, and over it after.
    void sweep_group(int group, const Pass& pass, double* alpha, factor_kernels::SweepColumns& cols,
                     ForwardPass* forward = nullptr);
    /// sweep_group's work at its k-th place: one column, or two of a supernode (nests_next)
    /// taken together. Returns how many columns.
    int sweep_at(std::span<const int> places, std::size_t k, std::size_t slots, double* alpha,
                 factor_kernels::SweepColumns& cols);
    /// α of the pass's changes that start in `group`, copied `from` → `to`.
    void take_alpha(const Pass& pass, std::span<const std::pair<int, int>> rows, int group, const double* from,
                    double* to) const;
    /// The second thread's counts and failure added to `columns`.
    void merge_second_columns();

    /// follow's bookkeeping: the contact flags taken over, the changes since the factor's
    /// contact set found, those outside L's pattern applied by CHOLMOD (which allocates their
    /// fill), the others listed in sweep_rows (updates first). Returns (changes, updates in
    /// sweep_rows).
    std::pair<int, std::size_t> gather_changes(std::span<const ContactPair> pairs,
                                               std::span<const std::uint8_t> in_contact);
    /// gather_changes' pass over pairs [from, to): their contacts stored from contacts[at] on,
    /// their changes since `factored` appended to `formed_to` and `broken_to` (ascending) and
    /// taken into `factored`. Pairs before `stores_end` store their slot without a branch on
    /// the (unpredictable) contact flag, a pair not touching into the place the next contact
    /// takes; those after it only where they touch. Returns how many touch.
    std::size_t gather_range(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                             std::size_t from, std::size_t stores_end, std::size_t to, std::size_t at,
                             std::vector<std::size_t>& formed_to, std::vector<std::size_t>& broken_to);

    /// Column j's pivot (at workspace place `slot`) through its changes in turn, the changes
    /// passed on to its parent, and the coefficients of the changes (those whose w is not
    /// exactly zero here) for its entries: into step_p, step_beta, step_w (Second = 0) or
    /// step_p2, step_beta2, step_w2 (1, the second column of a pair) of `cols`. Returns how
    /// many.
    template <int Second>
    int column_pivots(factor_kernels::SweepColumns& cols, int j, std::size_t slot, std::size_t slots, double* alpha);
    /// The tree after a change of L's pattern, and its split once two threads may use it.
    void find_etree_if_stale() {
        if (etree.size() != static_cast<std::size_t>(n)) find_etree();
        if (!split_computed && two_threads(n)) split_tree();
    }

    /// The elimination tree of L's pattern: a column's parent is its first row below the
    /// diagonal (−1 at a root). Cleared whenever the pattern may change.
    std::vector<int> etree;
    void find_etree();
    std::vector<std::uint8_t> nests_next;  // column j + 1's rows are column j's after its first
    /// The tree's split for two threads (split_tree): columns [0, split_mid) are group 0,
    /// [split_mid, split_top) group 1 (no column's parent crosses from one to the other), and
    /// [split_top, n) the top, which holds every ancestor of both. The top is chosen to minimise
    /// the estimated sweep time (top + the heavier group), the groups to halve the sweep and
    /// the passes over L. The crossing check alone makes each group a set of whole subtrees
    /// (postorder, which fill may break, is not assumed). Without a split, split_mid = split_top
    /// = n. Computed with the tree on two threads only (split_computed); a split that still
    /// holds after fill is kept, and a new L (analysis, factorisation) resets it.
    void split_tree();
    void choose_split(std::span<const double> own);  // split_tree's choice of split_mid and split_top
    /// The choice of split_mid below the top [top_from, n), given each column's share of a
    /// sweep (sweep_shares); no split (split_mid = split_top = n) if no boundary halves them.
    void split_groups(int top_from, std::span<const double> own);
    std::vector<double> sweep_shares() const;
    void find_split_tails();  // and of split_tails
    int split_mid = 0, split_top = 0;
    int kept_mid = 0, kept_top = 0;                      // the split before fill changed the tree (n: none)
    std::vector<factor_kernels::SplitTail> split_tails;  // group 1's columns with rows in the top
    static constexpr int kTopGroup = 2;
    int group_of(int j) const { return j < split_mid ? 0 : j < split_top ? 1 : kTopGroup; }
    /// Whether the sweep and the solves run split over two threads.
    bool split_usable() const { return two_threads(n) && split_computed && is_split(split_mid, split_top); }
    /// Whether (mid, top) splits the columns into two groups and a top (n: none).
    bool is_split(int mid, int top) const { return mid < top && top < n; }
    bool split_computed = false;
    std::vector<int> group_slots[3];  // a pass's workspace places by column group
    /// Steps of follow_and_solve and solve on two threads (cholmod_solve.cpp): the last
    /// pass of the sweep (`last`, α in `alpha`; none for a solve alone) and the solve of
    /// both right-hand sides, the groups side by side.
    void split_step(const Pass* last, std::span<const std::pair<int, int>> rows, double* alpha, const double* b_x,
                    const double* b_y, double* u_x, double* u_y);
    /// The same step on one thread: the last pass's groups in turn (`alpha_second`: group 1's
    /// α, as in split_step), the forward pass behind the sweep, then the backward pass, into
    /// `y` (xy); the right-hand sides permuted in, the solution not permuted out.
    void one_thread_step(const Pass* last, std::span<const std::pair<int, int>> rows, double* alpha,
                         double* alpha_second, const double* b_x, const double* b_y, double* y);
    std::vector<int> slot_of;  // sweep: a row's place in the workspace
    // The sweep's entry updates and their coefficients, and the same for the second thread
    // (each on cache lines of its own: each thread writes its own on every column).
    alignas(64) factor_kernels::SweepColumns columns;
    alignas(64) factor_kernels::SweepColumns second_columns;

    /// LDLᵀ ← LDLᵀ ± W Wᵀ, W's columns P (e_i − e_j) for the listed pairs (all at once).
    void modify(bool update, std::span<const ContactPair> pairs, const std::vector<std::size_t>& which);
};

}  // namespace jamsim::linalg
