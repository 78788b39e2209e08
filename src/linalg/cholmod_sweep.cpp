// The sweep of the updated CD0 factor: a step's contact changes applied to L in place, in one
// pass over the union of their elimination-tree paths (cholmod_factor.hpp, `follow`).
#include "cholmod_factor_impl.hpp"

namespace jamsim::linalg {

using factor_kernels::ColumnChanges;

template <int Second>
[[gnu::always_inline]] inline int CholmodUpdatedFactor::Impl::column_pivots(int j, std::size_t slot, std::size_t slots,
                                                                            double* alpha) {
    double* const ps = Second ? columns.step_p2 : columns.step_p;
    double* const betas = Second ? columns.step_beta2 : columns.step_beta;
    double** const ws = Second ? columns.step_w2 : columns.step_w;
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
        if (!(dbar > 0.0)) columns.failed = true;
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

void CholmodUpdatedFactor::Impl::sweep(std::span<const std::pair<int, int>> rows, std::size_t n_up,
                                       std::atomic<int>* done_below) {
    const auto* Lp = static_cast<const int*>(L->p);
    const auto* Li = static_cast<const int*>(L->i);
    const auto* Lnz = static_cast<const int*>(L->nz);
    auto* Lx = static_cast<double*>(L->x);
    const auto un = static_cast<std::size_t>(n);
    if (on_path.size() != un) {
        on_path.assign(un, 0);
        union_bits.assign((un + 63) / 64, 0);
        slot_of.assign(un, 0);
        columns.slot_rows.resize(un);
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
        const bool last_pass = start + kSweepRank >= rows.size();
        std::atomic<int>* const publish = last_pass ? done_below : nullptr;
        for (std::size_t slot = 0; slot < slots; ++slot) {
            const int j = path_union[slot];
            if (publish) publish->store(j, std::memory_order_release);
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
                if (count > 0) columns.apply_entry(l[0], static_cast<int>(slot) + 1, count);
                const int count2 = column_pivots<1>(j + 1, slot + 1, slots, alpha);
                ++slot;
                if (count == 0 && count2 == 0) continue;
                const int len2 = len - 1;
                const int* rows_j = Li + begin + 2;
                int* slots_j = columns.slot_rows.data();
                for (int e = 0; e < len2; ++e) slots_j[e] = slot_of[static_cast<std::size_t>(rows_j[e])];
                double* l2 = Lx + Lp[j + 1] + 1;
                if (count > 0 && count == count2 &&
                    std::equal(columns.step_w, columns.step_w + count, columns.step_w2)) {
                    columns.apply_pair(l + 1, l2, slots_j, len2, count);
                    continue;
                }
                // Different changes in the two columns (another child of j + 1 brings its
                // own): column after column, the second column's coefficients moved into
                // the first's arrays, which the single-column kernels read.
                if (count > 0) columns.apply_column(l + 1, slots_j, len2, count);
                if (count2 > 0) {
                    std::copy(columns.step_p2, columns.step_p2 + count2, columns.step_p);
                    std::copy(columns.step_beta2, columns.step_beta2 + count2, columns.step_beta);
                    std::copy(columns.step_w2, columns.step_w2 + count2, columns.step_w);
                    columns.apply_column(l2, slots_j, len2, count2);
                }
                continue;
            }
            if (count == 0 || len == 0) continue;
            const int* rows_j = Li + begin + 1;
            int* slots_j = columns.slot_rows.data();
            for (int e = 0; e < len; ++e) slots_j[e] = slot_of[static_cast<std::size_t>(rows_j[e])];
            columns.apply_column(l, slots_j, len, count);
        }
    }
    if (done_below) done_below->store(n, std::memory_order_release);
}

void CholmodUpdatedFactor::Impl::find_etree() {
    const auto* Lp = static_cast<const int*>(L->p);
    const auto* Li = static_cast<const int*>(L->i);
    const auto* Lnz = static_cast<const int*>(L->nz);
    etree.resize(static_cast<std::size_t>(n));
    for (int j = 0; j < n; ++j) etree[static_cast<std::size_t>(j)] = Lnz[j] > 1 ? Li[Lp[j] + 1] : -1;
    nests_next.assign(static_cast<std::size_t>(n), 0);
    for (int j = 0; j + 1 < n; ++j) {
        const int len = Lnz[j] - 1;
        if (len < 2 || Li[Lp[j] + 1] != j + 1 || Lnz[j + 1] != len) continue;
        nests_next[static_cast<std::size_t>(j)] = std::equal(Li + Lp[j] + 2, Li + Lp[j] + 1 + len, Li + Lp[j + 1] + 1);
    }
}

}  // namespace jamsim::linalg
