// The solves of the updated CD0 factor (cholmod_factor.hpp): x = Pᵀ L⁻ᵀ D⁻¹ L⁻¹ P b for both
// right-hand sides, on one thread in one pass over L for both, and on several with the rows
// below the top of the elimination tree's large supernodes split over the threads.
#include <omp.h>

#include "cholmod_factor_impl.hpp"

namespace jamsim::linalg {

using factor_kernels::load;
using factor_kernels::Pair;
using factor_kernels::ScopeTimer;
using factor_kernels::store;

namespace {

/// L's arrays and the solve's workspace: row r of `y` holds (x, y) as one SIMD pair at
/// y + 2 r, so each entry of L is read once per pass for both right-hand sides.
struct PairedSolve {
    const int* Lp;
    const int* Li;
    const int* Lnz;
    const double* Lx;
    double* y;

    explicit PairedSolve(const cholmod_factor& L, double* work)
        : Lp(static_cast<const int*>(L.p)), Li(static_cast<const int*>(L.i)), Lnz(static_cast<const int*>(L.nz)),
          Lx(static_cast<const double*>(L.x)), y(work) {}

    /// L z = P b, columns [from, to) in turn: each scatters its y_j into the rows below.
    /// (No test for a zero y_j: few columns have one, even at φ = 0.80, where the test cost
    /// more than it saved; skipping one gives the same bits.)
    [[gnu::always_inline]] void forward(int from, int to) const {
        for (int j = from; j < to; ++j) {
            const Pair yj = load(y + 2 * j);
            const int begin = Lp[j], end = begin + Lnz[j];
            for (int p = begin + 1; p < end; ++p) {
                double* at = y + 2 * Li[p];
                store(at, load(at) - Lx[p] * yj);
            }
        }
    }

    /// Lᵀ x = D⁻¹ z, columns (rows of Lᵀ) `from` down to `to`, each row's D⁻¹ applied as it
    /// is reached: the pivot Lx[begin] is then the next entry of the downward stream, where a
    /// pass of its own read one scattered cache line per column (0.3 ms of a step at
    /// N = 65536). Four partial sums (independent chains; a fixed order, so deterministic),
    /// each column read from its end down, so that the whole pass walks L's arrays downwards
    /// as one stream the hardware prefetcher follows: read upwards within columns taken in
    /// reverse, the short columns defeat it and at N = 65536 (L far larger than the cache)
    /// this pass took twice as long as the forward one. `groups` groups of four entries from
    /// the column's end are already summed into s (the threaded solve's rows below a
    /// supernode); the rest continue in the same order, so the same bits.
    [[gnu::always_inline]] void backward_column(int j, int groups, Pair s0, Pair s1, Pair s2, Pair s3) const {
        const int begin = Lp[j], end = begin + Lnz[j];
        int p = end - 4 * groups;
        for (; p - 4 >= begin + 1; p -= 4) {
            s0 += Lx[p - 1] * load(y + 2 * Li[p - 1]);
            s1 += Lx[p - 2] * load(y + 2 * Li[p - 2]);
            s2 += Lx[p - 3] * load(y + 2 * Li[p - 3]);
            s3 += Lx[p - 4] * load(y + 2 * Li[p - 4]);
        }
        for (; p > begin + 1; --p) s0 += Lx[p - 1] * load(y + 2 * Li[p - 1]);
        store(y + 2 * j, load(y + 2 * j) / Lx[begin] - ((s0 + s1) + (s2 + s3)));
    }
    [[gnu::always_inline]] void backward(int from, int to) const {
        const Pair zero{0.0, 0.0};
        for (int j = from; j >= to; --j) backward_column(j, 0, zero, zero, zero, zero);
    }

    /// The first `groups` groups of four entries from the end of column j, summed as
    /// `backward_column` sums them, into s[0, 4).
    [[gnu::always_inline]] void backward_groups(int j, int groups, Pair* s) const {
        Pair s0{0.0, 0.0}, s1{0.0, 0.0}, s2{0.0, 0.0}, s3{0.0, 0.0};
        int p = Lp[j] + Lnz[j];
        for (int g = 0; g < groups; ++g, p -= 4) {
            s0 += Lx[p - 1] * load(y + 2 * Li[p - 1]);
            s1 += Lx[p - 2] * load(y + 2 * Li[p - 2]);
            s2 += Lx[p - 3] * load(y + 2 * Li[p - 3]);
            s3 += Lx[p - 4] * load(y + 2 * Li[p - 4]);
        }
        s[0] = s0;
        s[1] = s1;
        s[2] = s2;
        s[3] = s3;
    }

    /// The forward pass of a panel's entries below it in rows [from, to): each row takes the
    /// panel's columns in order, as column after column does. `inside` per column as in
    /// Impl::inside.
    [[gnu::always_inline]] void forward_below(factor_kernels::Panel panel, const int* inside, int from, int to) const {
        for (int c = panel.first; c <= panel.last; ++c) {
            const Pair yc = load(y + 2 * c);
            const int* rows = Li + Lp[c] + 1 + inside[c];
            const int* end = Li + Lp[c] + Lnz[c];
            const int* lo = std::lower_bound(rows, end, from);
            const int* hi = std::lower_bound(lo, end, to);
            const double* l = Lx + (lo - Li);
            for (const int* r = lo; r < hi; ++r, ++l) {
                double* at = y + 2 * *r;
                store(at, load(at) - *l * yc);
            }
        }
    }

    /// The forward pass of a panel's triangle: its columns' entries in the panel's rows.
    [[gnu::always_inline]] void forward_triangle(factor_kernels::Panel panel, const int* inside) const {
        for (int c = panel.first; c <= panel.last; ++c) {
            const Pair yc = load(y + 2 * c);
            const int begin = Lp[c] + 1;
            for (int p = begin; p < begin + inside[c]; ++p) {
                double* at = y + 2 * Li[p];
                store(at, load(at) - Lx[p] * yc);
            }
        }
    }
};

/// [lo, hi) of `count` items for thread t of `threads`, in whole multiples of `align`.
std::pair<int, int> share(int count, int t, int threads, int align) {
    const int units = (count + align - 1) / align;
    const auto bound = [&](int k) { return std::min(count, align * static_cast<int>(1L * units * k / threads)); };
    return {bound(t), bound(t + 1)};
}

}  // namespace

void CholmodUpdatedFactor::solve(const double* b, double* x) {
    const auto n = static_cast<std::size_t>(impl_->n);
    solve(b, b + n, x, x + n);
}

void CholmodUpdatedFactor::solve(const double* b_x, const double* b_y, double* u_x, double* u_y) {
    Impl& m = *impl_;
    const ScopeTimer timer(m.counts.solve_seconds, m.timing);
    const int n = m.n;
    if (kernel_threads() > 1 && static_cast<std::size_t>(n) >= kThreadedLoopMin) {
        m.solve_blocked(b_x, b_y, u_x, u_y);
        return;
    }
    const auto* perm = static_cast<const int*>(m.L->Perm);
    m.xy.resize(2 * static_cast<std::size_t>(n));
    const PairedSolve s(*m.L, m.xy.data());
    for (int k = 0; k < n; ++k) {
        s.y[2 * k] = b_x[perm[k]];
        s.y[2 * k + 1] = b_y[perm[k]];
    }
    s.forward(0, n);
    s.backward(n - 1, 0);
    // Out through pinv (row of each disk): sequential stores and one (x, y) load per disk,
    // where storing through perm wrote two scattered lines per row.
    const int* pinv = m.pinv.data();
    for (int i = 0; i < n; ++i) {
        const Pair xi = load(s.y + 2 * pinv[i]);
        u_x[i] = xi[0];
        u_y[i] = xi[1];
    }
}

// The paired solve's operations on several threads, in one parallel region. The first thread
// takes the columns in order, as on one thread, up to each large panel (solve_blocks: chains
// of the elimination tree, the separators at the top of the nested-dissection tree, which
// hold half of L's entries) and its triangle; then all threads take the entries below it:
//  - forward, each thread a share of the rows, each row taking the panel's columns in order
//    (the same operations in the same order per entry as column after column);
//  - backward, each thread a share of the columns, summing the column's entries below the
//    panel into its four partial sums, which come first (each column is summed from its end
//    down); the first thread then continues each column's sums over the triangle, in order.
// Two barriers per panel. The same bits as on one thread.
void CholmodUpdatedFactor::Impl::solve_blocked(const double* b_x, const double* b_y, double* u_x, double* u_y) {
    if (etree.size() != static_cast<std::size_t>(n)) find_etree();
    ++counts.split_solves;
    const auto* perm = static_cast<const int*>(L->Perm);
    xy.resize(2 * static_cast<std::size_t>(n));
    block_sums.resize(4 * kPanel);
    const cholmod_factor& factor = *L;
    double* const work = xy.data();
    Pair* sums = block_sums.data();
    const int* pinv_rows = pinv.data();
    const int* in = inside.data();
    const auto* Lnz = static_cast<const int*>(L->nz);
    const auto* Lp = static_cast<const int*>(L->p);
    const auto* Li = static_cast<const int*>(L->i);
    const TimedRegion timed;
#pragma omp parallel
    {
        // Each thread's own copy of L's pointers: a local object, kept in registers, where a
        // shared one would be read again after every store into y.
        const PairedSolve solve(factor, work);
        const int t = omp_get_thread_num(), threads = omp_get_num_threads();
        const auto [in_lo, in_hi] = share(n, t, threads, 64);
        for (int k = in_lo; k < in_hi; ++k) {
            solve.y[2 * k] = b_x[perm[k]];
            solve.y[2 * k + 1] = b_y[perm[k]];
        }
#pragma omp barrier
        int j = 0;
        for (const Panel& panel : solve_blocks) {
            if (t == 0) {
                solve.forward(j, panel.first);
                solve.forward_triangle(panel, in);
            }
#pragma omp barrier
            // The rows below the panel (column `last`'s, which hold every column's): a share.
            const int* rows = Li + Lp[panel.last] + 1;
            const int below = Lnz[panel.last] - 1;
            const auto [lo, hi] = share(below, t, threads, 8);
            solve.forward_below(panel, in, lo < below ? rows[lo] : n, hi < below ? rows[hi] : n);
#pragma omp barrier
            j = panel.last + 1;
        }
        if (t == 0) solve.forward(j, n);
#pragma omp barrier
        j = n - 1;
        for (auto it = solve_blocks.rbegin(); it != solve_blocks.rend(); ++it) {
            const Panel& panel = *it;
            const auto groups = [&](int col) { return (Lnz[col] - 1 - in[col]) / 4; };
            if (t == 0) solve.backward(j, panel.last + 1);
#pragma omp barrier
            const auto [lo, hi] = share(panel.last - panel.first + 1, t, threads, 1);
            for (int col = panel.first + lo; col < panel.first + hi; ++col)
                solve.backward_groups(col, groups(col), sums + 4 * (col - panel.first));
#pragma omp barrier
            if (t == 0)
                for (int col = panel.last; col >= panel.first; --col) {
                    const Pair* sc = sums + 4 * (col - panel.first);
                    solve.backward_column(col, groups(col), sc[0], sc[1], sc[2], sc[3]);
                }
            j = panel.first - 1;
        }
        if (t == 0) solve.backward(j, 0);
#pragma omp barrier
        for (int i = in_lo; i < in_hi; ++i) {
            const Pair xi = load(solve.y + 2 * pinv_rows[i]);
            u_x[i] = xi[0];
            u_y[i] = xi[1];
        }
    }
}

}  // namespace jamsim::linalg
