#include "cholmod_factor.hpp"

#include <cholmod.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <utility>
#include <stdexcept>
#include <string>

namespace jamsim::linalg {

namespace {
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

/// Two doubles as one SIMD register (GCC/Clang vector extension; element-wise, so the
/// results are bitwise those of scalar code on every target).
using Pair = double __attribute__((vector_size(16)));
Pair load(const double* at) {
    Pair v;
    std::memcpy(&v, at, sizeof v);
    return v;
}
void store(double* at, Pair v) { std::memcpy(at, &v, sizeof v); }

/// The coefficients of a column's changes in the sweep: for change s, p[s] (the column's
/// workspace entry), beta[s] and w[s] (its workspace, indexed by place).
struct ColumnChanges {
    const double* p;
    const double* beta;
    double* const* w;
};

// The sweep's kernels for columns whose rows are consecutive places in the workspace (the
// dense separators at the top of the tree, where every change's path ends and most of the
// entry updates are): whole blocks of rows, `kVecs` vectors of V per column; they return how
// many rows they did (the caller does the rest entry by entry). Element-wise vector
// arithmetic without contraction into FMAs, so every vector width gives the same bits as
// scalar code: the width is only a matter of speed. Each entry's chain of operations runs
// through all the column's changes in turn, so a block needs enough independent rows to
// hide that chain's latency: blocks of 16 rows (8 SSE2 pairs, 4 AVX2 quads or 2 AVX-512
// octets per column; for two columns with SSE2 only 8, the most its 16 registers hold), then
// a tier of 8 rows.
// (Loads and stores by memcpy written out in the kernels: a helper returning a 32-byte
// vector would be a default-target function with an AVX ABI.)
#define JAMSIM_LOAD(V, dst, at) std::memcpy(&(dst), (at), sizeof(V))
#define JAMSIM_STORE(at, src) std::memcpy((at), &(src), sizeof(src))

/// One column: for each change s in order, w_r ← w_r − p l_r, then l_r ← l_r + β w_r.
template <class V, int kVecs>
[[gnu::always_inline]] inline int consecutive_blocks(ColumnChanges c, double* l, int row0, int len, int count) {
    constexpr int kWidth = static_cast<int>(sizeof(V) / sizeof(double));
    int k = 0;
    for (; k + kWidth * kVecs <= len; k += kWidth * kVecs) {
        V v[kVecs];
        for (int u = 0; u < kVecs; ++u) JAMSIM_LOAD(V, v[u], l + k + kWidth * u);
        for (int s = 0; s < count; ++s) {
            double* wr = c.w[s] + row0 + k;
            const double p = c.p[s], beta = c.beta[s];
            for (int u = 0; u < kVecs; ++u) {
                V wk;
                JAMSIM_LOAD(V, wk, wr + kWidth * u);
                wk = wk - p * v[u];
                JAMSIM_STORE(wr + kWidth * u, wk);
                v[u] += beta * wk;
            }
        }
        for (int u = 0; u < kVecs; ++u) JAMSIM_STORE(l + k + kWidth * u, v[u]);
    }
    return k;
}

/// Two columns of a pair over the same rows and changes (the second column's coefficients
/// in `second`, its workspaces those of `first`): per entry and change, the first column's
/// step before the second's, as column after column.
template <class V, int kVecs>
[[gnu::always_inline]] inline int consecutive2_blocks(ColumnChanges first, ColumnChanges second, double* l1,
                                                     double* l2, int row0, int len, int count) {
    constexpr int kWidth = static_cast<int>(sizeof(V) / sizeof(double));
    int k = 0;
    for (; k + kWidth * kVecs <= len; k += kWidth * kVecs) {
        V v1[kVecs], v2[kVecs];
        for (int u = 0; u < kVecs; ++u) {
            JAMSIM_LOAD(V, v1[u], l1 + k + kWidth * u);
            JAMSIM_LOAD(V, v2[u], l2 + k + kWidth * u);
        }
        for (int s = 0; s < count; ++s) {
            double* wr = first.w[s] + row0 + k;
            const double p1 = first.p[s], beta1 = first.beta[s], p2 = second.p[s], beta2 = second.beta[s];
            for (int u = 0; u < kVecs; ++u) {
                V wk;
                JAMSIM_LOAD(V, wk, wr + kWidth * u);
                wk = wk - p1 * v1[u];
                v1[u] += beta1 * wk;
                wk = wk - p2 * v2[u];
                JAMSIM_STORE(wr + kWidth * u, wk);
                v2[u] += beta2 * wk;
            }
        }
        for (int u = 0; u < kVecs; ++u) {
            JAMSIM_STORE(l1 + k + kWidth * u, v1[u]);
            JAMSIM_STORE(l2 + k + kWidth * u, v2[u]);
        }
    }
    return k;
}

#undef JAMSIM_LOAD
#undef JAMSIM_STORE

using ConsecutiveKernel = int (*)(ColumnChanges, double*, int, int, int);
using Consecutive2Kernel = int (*)(ColumnChanges, ColumnChanges, double*, double*, int, int, int);

/// Blocks of kVecs vectors (16 rows), then a tier of half as many (8 rows): runs of 8 or more
/// rows take these kernels (see by_runs).
template <class V, int kVecs>
[[gnu::always_inline]] inline int tiered_blocks(ColumnChanges c, double* l, int row0, int len, int count) {
    const int k = consecutive_blocks<V, kVecs>(c, l, row0, len, count);
    return k + consecutive_blocks<V, kVecs / 2>(c, l + k, row0 + k, len - k, count);
}
template <class V, int kVecs>
[[gnu::always_inline]] inline int tiered_blocks2(ColumnChanges a, ColumnChanges b, double* l1, double* l2, int row0,
                                                int len, int count) {
    const int k = consecutive2_blocks<V, kVecs>(a, b, l1, l2, row0, len, count);
    return k + consecutive2_blocks<V, kVecs / 2>(a, b, l1 + k, l2 + k, row0 + k, len - k, count);
}

int consecutive_sse2(ColumnChanges c, double* l, int row0, int len, int count) {
    return tiered_blocks<Pair, 8>(c, l, row0, len, count);
}
int consecutive2_sse2(ColumnChanges a, ColumnChanges b, double* l1, double* l2, int row0, int len, int count) {
    return consecutive2_blocks<Pair, 4>(a, b, l1, l2, row0, len, count);  // 8 rows already
}

#if defined(__x86_64__) && defined(__GNUC__)
#define JAMSIM_HAVE_WIDE_KERNELS 1
using Quad = double __attribute__((vector_size(32)));
using Oct = double __attribute__((vector_size(64)));  // AVX-512's 32 registers hold 2 per column of a pair
__attribute__((target("avx2"))) int consecutive_avx2(ColumnChanges c, double* l, int row0, int len, int count) {
    return tiered_blocks<Quad, 4>(c, l, row0, len, count);
}
__attribute__((target("avx2"))) int consecutive2_avx2(ColumnChanges a, ColumnChanges b, double* l1, double* l2,
                                                      int row0, int len, int count) {
    return tiered_blocks2<Quad, 4>(a, b, l1, l2, row0, len, count);
}
__attribute__((target("avx512f"))) int consecutive_avx512(ColumnChanges c, double* l, int row0, int len, int count) {
    return tiered_blocks<Oct, 2>(c, l, row0, len, count);
}
__attribute__((target("avx512f"))) int consecutive2_avx512(ColumnChanges a, ColumnChanges b, double* l1, double* l2,
                                                          int row0, int len, int count) {
    return tiered_blocks2<Oct, 2>(a, b, l1, l2, row0, len, count);
}
#endif

/// The consecutive-row kernels of the widest vectors that `vectors` allows and the
/// processor has (the operating system's support of the registers included).
struct WideKernels {
    ConsecutiveKernel one = consecutive_sse2;
    Consecutive2Kernel two = consecutive2_sse2;
    const char* name = "sse2";
};
WideKernels choose_kernels(CholmodUpdatedFactor::Vectors vectors) {
    using Vectors = CholmodUpdatedFactor::Vectors;
    WideKernels k;
#ifdef JAMSIM_HAVE_WIDE_KERNELS
    __builtin_cpu_init();
    if (vectors == Vectors::best && __builtin_cpu_supports("avx512f"))
        return {consecutive_avx512, consecutive2_avx512, "avx512f"};
    if (vectors != Vectors::sse2 && __builtin_cpu_supports("avx2"))
        return {consecutive_avx2, consecutive2_avx2, "avx2"};
#else
    (void)vectors;
#endif
    return k;
}
} // namespace

struct CholmodUpdatedFactor::Impl {
    int n = 0;
    double delta = 0;
    cholmod_common c{};
    cholmod_sparse* A = nullptr;   // lower triangle (stype −1), pattern = candidate pairs
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
    std::vector<std::uint8_t> factored;     // contact set the factor represents
    std::vector<double> xy;                 // solve: the permuted right-hand sides, interleaved
    // Workspace of `sweep`: one column per change over the rows of the union of the changes'
    // elimination-tree paths, that union, and per column of L which changes pass through it.
    std::vector<double> w;
    std::vector<std::uint64_t> on_path;
    static constexpr std::uint64_t kVisited = std::uint64_t{1} << 63;
    std::vector<int> path_union;
    std::vector<std::uint64_t> union_bits;  // sweep: the union as a bitmap of columns (zero between sweeps)
    bool sweep_failed = false;
    Counts counts;
    bool timing = false;  // a ScopeTimer is counting
    bool have_factor = false;
    // The contacts of the last factorize(), adopt() or follow(): the first n_contacts entries
    // (follow() writes all pairs' slots without a branch, so the storage is as long as them).
    std::vector<ContactPair> contacts;
    std::size_t n_contacts = 0;
    std::vector<std::size_t> formed, broken, outside;
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
        const auto* Lp = static_cast<const int*>(L->p);
        const auto* Li = static_cast<const int*>(L->i);
        const auto* Lnz = static_cast<const int*>(L->nz);
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
    /// column after column). Sets sweep_failed when a downdate meets a pivot that is not
    /// positive (the caller refactors).
    static constexpr int kSweepRank = 63;
    void sweep(std::span<const std::pair<int, int>> rows, std::size_t n_up) {
        const auto* Lp = static_cast<const int*>(L->p);
        const auto* Li = static_cast<const int*>(L->i);
        const auto* Lnz = static_cast<const int*>(L->nz);
        auto* Lx = static_cast<double*>(L->x);
        const auto un = static_cast<std::size_t>(n);
        if (on_path.size() != un) {
            on_path.assign(un, 0);
            union_bits.assign((un + 63) / 64, 0);
            slot_of.assign(un, 0);
            slot_rows.resize(un);
        }
        if (etree.size() != un) find_etree();
        auto parent = [&](int j) { return etree[static_cast<std::size_t>(j)]; };
        double alpha[kSweepRank];
        for (std::size_t start = 0; start < rows.size(); start += kSweepRank) {
            const int rank = static_cast<int>(std::min<std::size_t>(kSweepRank, rows.size() - start));
            int lowest = n;
            for (int t = 0; t < rank; ++t) {
                const int a = rows[start + static_cast<std::size_t>(t)].first;
                alpha[t] = start + static_cast<std::size_t>(t) < n_up ? 1.0 : -1.0;
                // The path from a to the root, as far as an earlier change's path (whose
                // columns pass their changes on to their parents while they are processed).
                on_path[static_cast<std::size_t>(a)] |= std::uint64_t{1} << t;
                lowest = std::min(lowest, a);
                for (int j = a; j >= 0 && !(on_path[static_cast<std::size_t>(j)] & kVisited); j = parent(j)) {
                    on_path[static_cast<std::size_t>(j)] |= kVisited;
                    union_bits[static_cast<std::size_t>(j) / 64] |= std::uint64_t{1} << (j % 64);
                }
            }
            // The union in ascending order from its bitmap: paths run upwards (a column's parent
            // comes after it), so the words from the lowest start to the end.
            path_union.clear();
            for (std::size_t word = static_cast<std::size_t>(lowest) / 64; word < union_bits.size(); ++word)
                for (std::uint64_t bits = std::exchange(union_bits[word], 0); bits; bits &= bits - 1)
                    path_union.push_back(static_cast<int>(64 * word) + __builtin_ctzll(bits));
            // The workspace holds only the rows of the union (every row a change reaches is
            // on its path), in the union's order (slot_of): small enough for the cache, and
            // consecutive rows keep consecutive slots.
            const std::size_t slots = path_union.size();
            for (std::size_t k = 0; k < slots; ++k) slot_of[static_cast<std::size_t>(path_union[k])] = static_cast<int>(k);
            w.assign(static_cast<std::size_t>(rank) * slots, 0.0);
            for (int t = 0; t < rank; ++t) {
                const auto [a, b] = rows[start + static_cast<std::size_t>(t)];
                double* wt = w.data() + static_cast<std::size_t>(t) * slots;
                wt[slot_of[static_cast<std::size_t>(a)]] = 1.0;
                wt[slot_of[static_cast<std::size_t>(b)]] = -1.0;
            }
            for (std::size_t slot = 0; slot < slots; ++slot) {
                const int j = path_union[slot];
                // The pivot's recurrence, change after change; then each entry of the column
                // takes every change in turn (its arithmetic is that of one change at a time).
                const int begin = Lp[j];
                const int count = column_pivots<0>(j, slot, slots, alpha);
                const int len = Lnz[j] - 1;  // entries below the diagonal
                double* l = Lx + begin + 1;
                // Column j + 1 nests in column j (a supernode: its rows are j's after the
                // first) and is next in the union: after j's first entry (row j + 1, which
                // gives j + 1 its pivots) both columns take their changes row by row, each
                // workspace entry loaded and stored once for both. Every entry gets the same
                // operations in the same order as column after column, so the same bits.
                if (nests_next[static_cast<std::size_t>(j)] && slot + 1 < slots && path_union[slot + 1] == j + 1) {
                    if (count > 0) apply_entry(l[0], static_cast<int>(slot) + 1, count);
                    const int count2 = column_pivots<1>(j + 1, slot + 1, slots, alpha);
                    ++slot;
                    if (count == 0 && count2 == 0) continue;
                    const int len2 = len - 1;
                    const int* rows_j = Li + begin + 2;
                    int* slots_j = slot_rows.data();
                    for (int e = 0; e < len2; ++e) slots_j[e] = slot_of[static_cast<std::size_t>(rows_j[e])];
                    double* l2 = Lx + Lp[j + 1] + 1;
                    if (count > 0 && count == count2 && std::equal(step_w, step_w + count, step_w2)) {
                        apply_pair(l + 1, l2, slots_j, len2, count);
                        continue;
                    }
                    // Different changes in the two columns (another child of j + 1 brings its
                    // own): column after column, the second column's coefficients moved into
                    // the first's arrays, which the single-column kernels read.
                    if (count > 0) apply_column(l + 1, slots_j, len2, count);
                    if (count2 > 0) {
                        std::copy(step_p2, step_p2 + count2, step_p);
                        std::copy(step_beta2, step_beta2 + count2, step_beta);
                        std::copy(step_w2, step_w2 + count2, step_w);
                        apply_column(l2, slots_j, len2, count2);
                    }
                    continue;
                }
                if (count == 0 || len == 0) continue;
                const int* rows_j = Li + begin + 1;
                int* slots_j = slot_rows.data();
                for (int e = 0; e < len; ++e) slots_j[e] = slot_of[static_cast<std::size_t>(rows_j[e])];
                apply_column(l, slots_j, len, count);
            }
        }
    }

    /// Column j's pivot (at workspace place `slot`) through its changes in turn, the changes
    /// passed on to its parent, and the coefficients of the changes (those whose w is not
    /// exactly zero here) for its entries: into step_p, step_beta, step_w (Second = 0) or
    /// step_p2, step_beta2, step_w2 (1, the second column of a pair). Returns how many.
    template <int Second>
    [[gnu::always_inline]] int column_pivots(int j, std::size_t slot, std::size_t slots, double* alpha) {
        double* const ps = Second ? step_p2 : step_p;
        double* const betas = Second ? step_beta2 : step_beta;
        double** const ws = Second ? step_w2 : step_w;
        auto* Lx = static_cast<double*>(L->x);
        const int begin = static_cast<const int*>(L->p)[j];
        const std::uint64_t here = on_path[static_cast<std::size_t>(j)] & ~kVisited;
        on_path[static_cast<std::size_t>(j)] = 0;
        if (const int up = etree[static_cast<std::size_t>(j)]; up >= 0) on_path[static_cast<std::size_t>(up)] |= here;
        int count = 0;
        for (std::uint64_t active = here; active; active &= active - 1) {
            const int t = __builtin_ctzll(active);
            double* wt = w.data() + static_cast<std::size_t>(t) * slots;
            const double p = wt[slot];
            if (p == 0.0) continue;
            const double d = Lx[begin];
            const double dbar = d + alpha[t] * p * p;
            if (!(dbar > 0.0)) sweep_failed = true;
            const double inv = 1.0 / dbar;
            ps[count] = p;
            betas[count] = p * alpha[t] * inv;
            ws[count] = wt;
            ++count;
            alpha[t] *= d * inv;
            Lx[begin] = dbar;
        }
        return count;
    }

    /// The elimination tree of L's pattern: a column's parent is its first row below the
    /// diagonal (−1 at a root). Cleared whenever the pattern may change.
    std::vector<int> etree;
    void find_etree() {
        const auto* Lp = static_cast<const int*>(L->p);
        const auto* Li = static_cast<const int*>(L->i);
        const auto* Lnz = static_cast<const int*>(L->nz);
        etree.resize(static_cast<std::size_t>(n));
        for (int j = 0; j < n; ++j) etree[static_cast<std::size_t>(j)] = Lnz[j] > 1 ? Li[Lp[j] + 1] : -1;
        nests_next.assign(static_cast<std::size_t>(n), 0);
        for (int j = 0; j + 1 < n; ++j) {
            const int len = Lnz[j] - 1;
            if (len < 2 || Li[Lp[j] + 1] != j + 1 || Lnz[j + 1] != len) continue;
            nests_next[static_cast<std::size_t>(j)] =
                std::equal(Li + Lp[j] + 2, Li + Lp[j] + 1 + len, Li + Lp[j + 1] + 1);
        }
    }
    std::vector<std::uint8_t> nests_next;  // column j + 1's rows are column j's after its first
    std::vector<int> slot_of;    // sweep: a row's place in the workspace
    std::vector<int> slot_rows;  // sweep: a column's rows as places in the workspace

    // The changes of one column (step_p, step_beta, step_w) applied to its entries l[0, len),
    // whose rows are given as places in the workspace: for each change in order,
    // w_r ← w_r − p l_r, then l_r ← l_r + β w_r. Runs of consecutive places go to the
    // consecutive-row kernels (`consecutive_kernel`, `consecutive2_kernel`, chosen by vector
    // width), the other entries kBlock at a time (independent chains the processor overlaps).
    static constexpr int kBlock = 8;
    const char* vector_kernels = "sse2";  // the vectors of the kernels below
    ConsecutiveKernel consecutive_kernel = consecutive_sse2;
    Consecutive2Kernel consecutive2_kernel = consecutive2_sse2;
    double step_p[kSweepRank], step_beta[kSweepRank];
    double* step_w[kSweepRank];
    // The second column of a pair (see `sweep`): its changes' coefficients.
    double step_p2[kSweepRank], step_beta2[kSweepRank];
    double* step_w2[kSweepRank];

    /// A column's `count` changes (step_p, step_beta, step_w) on its entries l[0, len), whose
    /// workspace rows are `rows`.
    void apply_column(double* l, const int* rows, int len, int count) {
        by_runs(rows, len, [&](int from, int to) {
            const int k = consecutive_kernel(ColumnChanges{step_p, step_beta, step_w}, l + from, rows[from], to - from, count);
            counts.block_updates += static_cast<long>(k) * count;
            return from + k;
        }, [&](int from, int to) { apply_scattered(l + from, rows + from, to - from, count); });
    }

    /// The two columns of a pair on the same rows (the second column's coefficients in
    /// step_p2, step_beta2; the same changes): per entry and change, the first column's step
    /// before the second's, as column after column.
    void apply_pair(double* l1, double* l2, const int* rows, int len, int count) {
        by_runs(rows, len, [&](int from, int to) {
            const int k = consecutive2_kernel(ColumnChanges{step_p, step_beta, step_w},
                                              ColumnChanges{step_p2, step_beta2, step_w}, l1 + from, l2 + from,
                                              rows[from], to - from, count);
            counts.block_updates += 2L * k * count;
            return from + k;
        }, [&](int from, int to) { apply_scattered2(l1 + from, l2 + from, rows + from, to - from, count); });
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
        int rest = 0;  // entries from `rest` on are not done yet
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

    /// LDLᵀ ← LDLᵀ ± W Wᵀ, W's columns P (e_i − e_j) for the listed pairs (all at once).
    void modify(bool update, std::span<const ContactPair> pairs, const std::vector<std::size_t>& which) {
        if (which.empty()) return;
        const std::size_t k = which.size();
        cholmod_sparse* W = cholmod_allocate_sparse(static_cast<std::size_t>(n), k, 2 * k, 1, 1, 0,
                                                    CHOLMOD_REAL, &c);
        if (!W) fail("cholmod_allocate_sparse");
        auto* Wp = static_cast<int*>(W->p);
        auto* Wi = static_cast<int*>(W->i);
        auto* Wx = static_cast<double*>(W->x);
        for (std::size_t t = 0; t < k; ++t) {
            int a = pinv[static_cast<std::size_t>(pairs[which[t]].i)];
            int b = pinv[static_cast<std::size_t>(pairs[which[t]].j)];
            double va = 1.0, vb = -1.0;
            if (a > b) {
                std::swap(a, b);
                std::swap(va, vb);
            }
            Wp[t] = static_cast<int>(2 * t);
            Wi[2 * t] = a;
            Wx[2 * t] = va;
            Wi[2 * t + 1] = b;
            Wx[2 * t + 1] = vb;
        }
        Wp[k] = static_cast<int>(2 * k);
        const int ok = cholmod_updown(update ? 1 : 0, W, L, &c);
        etree.clear();  // an update may have added fill
        cholmod_free_sparse(&W, &c);
        if (!ok || c.status != CHOLMOD_OK) fail("cholmod_updown");
    }
};

CholmodUpdatedFactor::CholmodUpdatedFactor(std::size_t n, double delta, Ordering ordering, Vectors vectors)
    : impl_(new Impl{}) {
    Impl& m = *impl_;
    m.n = static_cast<int>(n);
    m.delta = delta;
    const WideKernels kernels = choose_kernels(vectors);
    m.consecutive_kernel = kernels.one;
    m.consecutive2_kernel = kernels.two;
    m.vector_kernels = kernels.name;
    cholmod_start(&m.c);
    m.c.print = 0;
    m.c.error_handler = nullptr;
    m.c.supernodal = CHOLMOD_SIMPLICIAL;  // updown needs a simplicial LDLᵀ
    m.c.final_ll = 0;
    m.c.nmethods = 1;
    m.c.method[0].ordering = ordering == Ordering::metis ? CHOLMOD_METIS : CHOLMOD_AMD;
    m.c.postorder = 1;
}

CholmodUpdatedFactor::~CholmodUpdatedFactor() {
    Impl& m = *impl_;
    if (m.A) cholmod_free_sparse(&m.A, &m.c);
    if (m.L) cholmod_free_factor(&m.L, &m.c);
    cholmod_finish(&m.c);
}

const char* CholmodUpdatedFactor::vector_kernels() const { return impl_->vector_kernels; }

bool CholmodUpdatedFactor::has_factor() const { return impl_->have_factor; }

CholmodUpdatedFactor::Counts CholmodUpdatedFactor::counts() const { return impl_->counts; }

std::span<const ContactPair> CholmodUpdatedFactor::contacts() const {
    return std::span<const ContactPair>(impl_->contacts).first(impl_->n_contacts);
}

void CholmodUpdatedFactor::analyse(std::span<const ContactPair> pairs) {
    Impl& m = *impl_;
    const int n = m.n;
    if (m.A) cholmod_free_sparse(&m.A, &m.c);
    if (m.L) cholmod_free_factor(&m.L, &m.c);
    m.have_factor = false;
    // A's pattern: the diagonal and every candidate pair, lower triangle, sorted columns.
    std::vector<int> count(static_cast<std::size_t>(n) + 1, 0);
    for (const auto& p : pairs) ++count[static_cast<std::size_t>(std::min(p.i, p.j)) + 1];
    for (std::size_t j = 0; j < static_cast<std::size_t>(n); ++j) count[j + 1] += count[j] + 1;
    const std::size_t nnz = static_cast<std::size_t>(count.back());
    m.A = cholmod_allocate_sparse(static_cast<std::size_t>(n), static_cast<std::size_t>(n), nnz, 1,
                                  1, -1, CHOLMOD_REAL, &m.c);
    if (!m.A) m.fail("cholmod_allocate_sparse");
    auto* Ap = static_cast<int*>(m.A->p);
    auto* Ai = static_cast<int*>(m.A->i);
    std::copy(count.begin(), count.end(), Ap);
    std::vector<int> fill(count.begin(), count.end() - 1);
    m.diag_slot.resize(static_cast<std::size_t>(n));
    for (int j = 0; j < n; ++j) {
        m.diag_slot[static_cast<std::size_t>(j)] = fill[static_cast<std::size_t>(j)];
        Ai[fill[static_cast<std::size_t>(j)]++] = j;
    }
    m.pair_slot.resize(pairs.size());
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        const int lo = std::min(pairs[k].i, pairs[k].j), hi = std::max(pairs[k].i, pairs[k].j);
        m.pair_slot[k] = fill[static_cast<std::size_t>(lo)];
        Ai[fill[static_cast<std::size_t>(lo)]++] = hi;
    }
    // Sort each column's rows (carrying the pair slots along): CHOLMOD wants sorted columns.
    std::vector<int> where(nnz);  // where[s] = pair index + 1 at slot s (0: diagonal)
    for (std::size_t k = 0; k < pairs.size(); ++k)
        where[static_cast<std::size_t>(m.pair_slot[k])] = static_cast<int>(k) + 1;
    std::vector<std::pair<int, int>> col;
    for (int j = 0; j < n; ++j) {
        col.clear();
        for (int s = Ap[j]; s < Ap[j + 1]; ++s) col.emplace_back(Ai[s], where[static_cast<std::size_t>(s)]);
        std::sort(col.begin(), col.end());
        for (std::size_t t = 0; t < col.size(); ++t) {
            const int s = Ap[j] + static_cast<int>(t);
            Ai[s] = col[t].first;
            if (col[t].second == 0) m.diag_slot[static_cast<std::size_t>(j)] = s;
            else m.pair_slot[static_cast<std::size_t>(col[t].second - 1)] = s;
        }
    }
    m.L = cholmod_analyze(m.A, &m.c);
    if (!m.L) m.fail("cholmod_analyze");
    const auto* perm = static_cast<const int*>(m.L->Perm);
    m.pinv.resize(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) m.pinv[static_cast<std::size_t>(perm[k])] = k;
    m.analysis_current = true;
}

bool CholmodUpdatedFactor::adopt(std::span<const ContactPair> pairs,
                                 std::span<const std::int32_t> labels) {
    Impl& m = *impl_;
    const ScopeTimer timer(m.counts.upkeep_seconds, m.timing);
    m.analysis_current = false;
    const auto n = static_cast<std::size_t>(m.n);
    if (!m.have_factor || labels.size() != n || m.labels.size() != n ||
        m.fill() > kFillGrowth * m.fresh_fill) {
        m.have_factor = false;
        m.labels.assign(labels.begin(), labels.end());
        return false;
    }
    // Row of L of each label, then the new rows' positions: the same disks, the same order.
    std::vector<int>& row_of_label = m.scratch;
    row_of_label.assign(n, -1);
    for (std::size_t i = 0; i < n; ++i) row_of_label[static_cast<std::size_t>(m.labels[i])] = m.pinv[i];
    std::vector<int> new_index(n, -1);  // by label
    for (std::size_t i = 0; i < n; ++i) {
        const auto label = static_cast<std::size_t>(labels[i]);
        if (label >= n || new_index[label] >= 0) throw std::invalid_argument("CD0 CHOLMOD factor: labels are not a permutation");
        new_index[label] = static_cast<int>(i);
    }
    auto* perm = static_cast<int*>(m.L->Perm);
    for (std::size_t i = 0; i < n; ++i) {
        const int row = row_of_label[static_cast<std::size_t>(labels[i])];
        m.pinv[i] = row;
        perm[row] = static_cast<int>(i);
    }
    // The factor's contacts in the new numbering, grouped by their lower disk (a disk has a
    // few), then matched against the new candidate pairs.
    const std::span<const ContactPair> factor_contacts = contacts();
    const std::size_t held = factor_contacts.size();
    std::vector<ContactPair> renamed(held);
    std::vector<int> first(n + 1, 0);  // held contacts of lower disk d: [first[d], first[d + 1])
    for (std::size_t t = 0; t < held; ++t) {
        const ContactPair& c = factor_contacts[t];
        const int a = new_index[static_cast<std::size_t>(m.labels[static_cast<std::size_t>(c.i)])];
        const int b = new_index[static_cast<std::size_t>(m.labels[static_cast<std::size_t>(c.j)])];
        renamed[t] = {a, b};
        ++first[static_cast<std::size_t>(std::min(a, b)) + 1];
    }
    for (std::size_t d = 0; d < n; ++d) first[d + 1] += first[d];
    std::vector<int> upper(held);        // the other disk of each grouped contact
    std::vector<std::size_t> which(held);  // and its place in `renamed`
    {
        std::vector<int> next(first.begin(), first.end() - 1);
        for (std::size_t t = 0; t < held; ++t) {
            const auto [a, b] = renamed[t];
            const auto at = static_cast<std::size_t>(next[static_cast<std::size_t>(std::min(a, b))]++);
            upper[at] = std::max(a, b);
            which[at] = t;
        }
    }
    std::vector<std::uint8_t> found(held, 0);
    m.factored.assign(pairs.size(), 0);
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        const auto lo = static_cast<std::size_t>(std::min(pairs[k].i, pairs[k].j));
        const int hi = std::max(pairs[k].i, pairs[k].j);
        for (int at = first[lo]; at < first[lo + 1]; ++at) {
            if (upper[static_cast<std::size_t>(at)] != hi) continue;
            m.factored[k] = 1;
            found[which[static_cast<std::size_t>(at)]] = 1;
            break;
        }
    }
    // Contacts of the factor that are no candidates any more (they broke): downdated now.
    std::vector<std::size_t> gone;
    for (std::size_t t = 0; t < held; ++t)
        if (!found[t]) gone.push_back(t);
    m.modify(false, renamed, gone);
    m.contacts.clear();
    for (std::size_t k = 0; k < pairs.size(); ++k)
        if (m.factored[k]) m.contacts.push_back(pairs[k]);
    m.n_contacts = m.contacts.size();
    m.labels.assign(labels.begin(), labels.end());
    return true;
}

void CholmodUpdatedFactor::factorize(std::span<const ContactPair> pairs,
                                     std::span<const std::uint8_t> in_contact) {
    Impl& m = *impl_;
    const ScopeTimer timer(m.counts.upkeep_seconds, m.timing);
    if (!m.analysis_current) analyse(pairs);
    auto* v = static_cast<double*>(m.A->x);
    for (const int s : m.diag_slot) v[s] = m.delta;
    m.contacts.clear();
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        if (in_contact[k]) m.contacts.push_back(pairs[k]);
        const double w = in_contact[k] ? 1.0 : 0.0;
        v[m.pair_slot[k]] = -w;
        v[m.diag_slot[static_cast<std::size_t>(pairs[k].i)]] += w;
        v[m.diag_slot[static_cast<std::size_t>(pairs[k].j)]] += w;
    }
    m.n_contacts = m.contacts.size();
    if (!cholmod_factorize(m.A, m.L, &m.c) || m.c.status != CHOLMOD_OK) m.fail("cholmod_factorize");
    m.etree.clear();
    m.factored.assign(in_contact.begin(), in_contact.end());
    m.have_factor = true;
    m.fresh_fill = m.fill();
}

int CholmodUpdatedFactor::follow(std::span<const ContactPair> pairs,
                                 std::span<const std::uint8_t> in_contact) {
    Impl& m = *impl_;
    const ScopeTimer timer(m.counts.upkeep_seconds, m.timing);
    m.formed.clear();
    m.broken.clear();
    // The contacts gathered without a branch on the (unpredictable) contact flag; changes
    // are rare, so their branch predicts well.
    if (m.contacts.size() < pairs.size()) m.contacts.resize(pairs.size());
    std::size_t touching = 0;
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        m.contacts[touching] = pairs[k];
        touching += in_contact[k] != 0;
        if (in_contact[k] == m.factored[k]) continue;
        (in_contact[k] ? m.formed : m.broken).push_back(k);
        m.factored[k] = in_contact[k];
    }
    m.n_contacts = touching;
    // Changes whose pattern L holds go through `sweep`, updates first (the factor stays well
    // away from singular), in one pass; contacts formed outside the pattern (possible after
    // `adopt`) make fill, which CHOLMOD's update allocates.
    m.sweep_rows.clear();
    m.outside.clear();
    int a = 0, b = 0;
    for (const std::size_t k : m.formed) {
        if (m.fits(pairs[k], a, b)) m.sweep_rows.emplace_back(a, b);
        else m.outside.push_back(k);
    }
    const std::size_t n_up = m.sweep_rows.size();
    for (const std::size_t k : m.broken) {
        if (!m.fits(pairs[k], a, b)) throw std::logic_error("CD0 CHOLMOD factor: a broken contact outside L's pattern");
        m.sweep_rows.emplace_back(a, b);
    }
    m.modify(true, pairs, m.outside);
    m.sweep(m.sweep_rows, n_up);
    m.counts.swept += static_cast<long>(m.sweep_rows.size());
    m.counts.filled += static_cast<long>(m.outside.size());
    if (m.sweep_failed) {  // a downdate lost positive definiteness (round-off): start afresh
        m.sweep_failed = false;
        ++m.counts.refactored;
        factorize(pairs, in_contact);
    }
    return static_cast<int>(m.formed.size() + m.broken.size());
}

void CholmodUpdatedFactor::solve(const double* b, double* x) {
    const auto n = static_cast<std::size_t>(impl_->n);
    solve(b, b + n, x, x + n);
}

void CholmodUpdatedFactor::solve(const double* b_x, const double* b_y, double* u_x, double* u_y) {
    // x = Pᵀ L⁻ᵀ D⁻¹ L⁻¹ P b on both right-hand sides at once: row r of `y` holds (x, y) as
    // one SIMD pair, so each entry of L is read once per pass for both.
    Impl& m = *impl_;
    const ScopeTimer timer(m.counts.solve_seconds, m.timing);
    const int n = m.n;
    const auto* Lp = static_cast<const int*>(m.L->p);
    const auto* Li = static_cast<const int*>(m.L->i);
    const auto* Lnz = static_cast<const int*>(m.L->nz);
    const auto* Lx = static_cast<const double*>(m.L->x);
    const auto* perm = static_cast<const int*>(m.L->Perm);
    m.xy.resize(2 * static_cast<std::size_t>(n));
    double* y = m.xy.data();  // row r at y + 2 r
    for (int k = 0; k < n; ++k) {
        y[2 * k] = b_x[perm[k]];
        y[2 * k + 1] = b_y[perm[k]];
    }
    // L z = P b, column by column. (No test for a zero y_j: few columns have one, even at
    // φ = 0.80, where the test cost more than it saved; skipping one gives the same bits.)
    for (int j = 0; j < n; ++j) {
        const Pair yj = load(y + 2 * j);
        const int begin = Lp[j], end = begin + Lnz[j];
        for (int p = begin + 1; p < end; ++p) {
            double* at = y + 2 * Li[p];
            store(at, load(at) - Lx[p] * yj);
        }
    }
    // Lᵀ x = D⁻¹ z, row by row of Lᵀ, each row's D⁻¹ applied as it is reached: the pivot
    // Lx[begin] is then the next entry of the downward stream, where a pass of its own read
    // one scattered cache line per column (0.3 ms of a step at N = 65536). The same
    // operations in the same order per row, so the same bits.
    for (int j = n - 1; j >= 0; --j) {
        const int begin = Lp[j], end = begin + Lnz[j];
        // Four partial sums (independent chains; a fixed order, so deterministic). Each
        // column is read from its end down, so that the whole pass walks L's arrays downwards
        // as one stream the hardware prefetcher follows: read upwards within columns taken in
        // reverse, the short columns defeat it and at N = 65536 (L far larger than the cache)
        // this pass took twice as long as the forward one.
        Pair s0{0.0, 0.0}, s1{0.0, 0.0}, s2{0.0, 0.0}, s3{0.0, 0.0};
        int p = end;
        for (; p - 4 >= begin + 1; p -= 4) {
            s0 += Lx[p - 1] * load(y + 2 * Li[p - 1]);
            s1 += Lx[p - 2] * load(y + 2 * Li[p - 2]);
            s2 += Lx[p - 3] * load(y + 2 * Li[p - 3]);
            s3 += Lx[p - 4] * load(y + 2 * Li[p - 4]);
        }
        for (; p > begin + 1; --p) s0 += Lx[p - 1] * load(y + 2 * Li[p - 1]);
        store(y + 2 * j, load(y + 2 * j) / Lx[begin] - ((s0 + s1) + (s2 + s3)));
    }
    // Out through pinv (row of each disk): sequential stores and one (x, y) load per disk,
    // where storing through perm wrote two scattered lines per row.
    const int* pinv = m.pinv.data();
    for (int i = 0; i < n; ++i) {
        const Pair xi = load(y + 2 * pinv[i]);
        u_x[i] = xi[0];
        u_y[i] = xi[1];
    }
}

} // namespace jamsim::linalg
