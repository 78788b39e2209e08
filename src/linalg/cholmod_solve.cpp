// The solves of the updated CD0 factor (cholmod_factor.hpp): x = Pᵀ L⁻ᵀ D⁻¹ L⁻¹ P b for
// both right-hand sides at once, on one thread or over the elimination tree's subtrees.
#include "cholmod_factor_impl.hpp"

namespace jamsim::linalg {

using factor_kernels::load;
using factor_kernels::Pair;
using factor_kernels::ScopeTimer;
using factor_kernels::store;

namespace {

/// The factor's arrays, read by the passes below.
struct Columns {
    const int* Lp;
    const int* Li;
    const int* Lnz;
    const double* Lx;
    explicit Columns(const cholmod_factor& L)
        : Lp(static_cast<const int*>(L.p)), Li(static_cast<const int*>(L.i)), Lnz(static_cast<const int*>(L.nz)),
          Lx(static_cast<const double*>(L.x)) {}

    /// Forward substitution of column j's entries [from, to) of L's arrays: y_i −= l_ij y_j.
    void forward(double* y, int j, int from, int to) const {
        const Pair yj = load(y + 2 * j);
        for (int p = from; p < to; ++p) {
            double* at = y + 2 * Li[p];
            store(at, load(at) - Lx[p] * yj);
        }
    }

    /// Row j of Lᵀ x = D⁻¹ z, its D⁻¹ applied as it is reached: the pivot Lx[begin] is then
    /// the next entry of the downward stream. Four partial sums (independent chains, a fixed
    /// order). Each column is read from its end down, so that a pass over columns taken in
    /// reverse walks L's arrays downwards as one stream the hardware prefetcher follows:
    /// read upwards within columns, the short columns defeat it, and at N = 65536 (L far
    /// larger than the cache) this pass took twice as long as the forward one.
    void backward(double* y, int j) const {
        const int begin = Lp[j], end = begin + Lnz[j];
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
};

} // namespace

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
    const auto un = static_cast<std::size_t>(n);
    const auto* perm = static_cast<const int*>(m.L->Perm);
    m.xy.resize(2 * un);
    double* const y = m.xy.data();  // row r at y + 2 r
    const bool threaded = kernel_threads() > 1 && un >= kThreadedLoopMin;
    parallel_for(un, [=](std::size_t k) {
        y[2 * k] = b_x[perm[k]];
        y[2 * k + 1] = b_y[perm[k]];
    });
    const Columns L(*m.L);
    if (!threaded) {
        // L z = P b, column by column. (No test for a zero y_j: few columns have one, even at
        // φ = 0.80, where the test cost more than it saved; skipping one gives the same bits.)
        for (int j = 0; j < n; ++j) L.forward(y, j, L.Lp[j] + 1, L.Lp[j] + L.Lnz[j]);
        for (int j = n - 1; j >= 0; --j) L.backward(y, j);
    } else {
        // Over the subtrees of `part` (cholmod_factor_impl.hpp). Forward: each subtree's
        // columns on their entries within the subtree, side by side; then, in column order,
        // the entries in rows of the top (the subtrees' tails, the top's columns). Each row
        // takes its updates in column order as in one pass, so the same bits. Backward: the
        // top's columns (they read only the top's rows), then each subtree's, side by side.
        if (m.etree.size() != un) m.find_etree();
        const auto part_range = [&](int g) {
            const auto from = static_cast<std::size_t>(m.part_column_start[static_cast<std::size_t>(g)]);
            const auto to = static_cast<std::size_t>(m.part_column_start[static_cast<std::size_t>(g) + 1]);
            return std::span<const int>(m.part_columns).subspan(from, to - from);
        };
#pragma omp parallel for schedule(dynamic, 1)
        for (int g = 0; g < m.parts; ++g)
            for (const int j : part_range(g)) L.forward(y, j, L.Lp[j] + 1, m.tail[static_cast<std::size_t>(j)]);
        for (const int j : m.top_and_tails) L.forward(y, j, m.tail[static_cast<std::size_t>(j)], L.Lp[j] + L.Lnz[j]);
        const std::span<const int> top = part_range(m.parts);
        for (auto j = top.rbegin(); j != top.rend(); ++j) L.backward(y, *j);
#pragma omp parallel for schedule(dynamic, 1)
        for (int g = 0; g < m.parts; ++g) {
            const std::span<const int> columns = part_range(g);
            for (auto j = columns.rbegin(); j != columns.rend(); ++j) L.backward(y, *j);
        }
    }
    // Out through pinv (row of each disk): sequential stores and one (x, y) load per disk,
    // where storing through perm wrote two scattered lines per row.
    const int* pinv = m.pinv.data();
    parallel_for(un, [=](std::size_t i) {
        const Pair xi = load(y + 2 * pinv[i]);
        u_x[i] = xi[0];
        u_y[i] = xi[1];
    });
}

} // namespace jamsim::linalg
