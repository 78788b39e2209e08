// The sweep of the updated CD0 factor: a step's contact changes applied to L in place, in one
// pass over the union of their elimination-tree paths (cholmod_factor.hpp, `follow`).
#include "cholmod_factor_impl.hpp"

namespace jamsim::linalg {

using factor_kernels::ColumnChanges;

template <int Second>
[[gnu::always_inline]] inline int CholmodUpdatedFactor::Impl::column_pivots(factor_kernels::SweepColumns& cols, int j,
                                                                        std::size_t slot, std::size_t slots,
                                                                        double* alpha, bool shared_parents) {
    double* const ps = Second ? cols.step_p2 : cols.step_p;
    double* const betas = Second ? cols.step_beta2 : cols.step_beta;
    double** const ws = Second ? cols.step_w2 : cols.step_w;
    auto* Lx = static_cast<double*>(L->x);
    const int begin = static_cast<const int*>(L->p)[j];
    const std::uint64_t here = on_path[static_cast<std::size_t>(j)] & ~kVisited;
    on_path[static_cast<std::size_t>(j)] = 0;
    if (const int up = etree[static_cast<std::size_t>(j)]; up >= 0) {
        // A subtree's root passes its changes to a column of the top, to which other
        // subtrees' roots may be passing theirs at the same moment.
        if (shared_parents && part[static_cast<std::size_t>(up)] != part[static_cast<std::size_t>(j)])
            __atomic_fetch_or(&on_path[static_cast<std::size_t>(up)], here, __ATOMIC_RELAXED);
        else
            on_path[static_cast<std::size_t>(up)] |= here;
    }
    int count = 0;
    for (std::uint64_t active = here; active; active &= active - 1) {
        const int t = __builtin_ctzll(active);
        double* wt = w.data() + static_cast<std::size_t>(t) * slots;
        const double p = wt[slot];
        if (p == 0.0) continue;
        const double d = Lx[begin];
        const double dbar = d + alpha[t] * p * p;
        if (!(dbar > 0.0)) cols.failed = true;
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

void CholmodUpdatedFactor::Impl::sweep_places(factor_kernels::SweepColumns& cols, std::span<const int> places,
                                              std::size_t slots, double* alpha, bool shared_parents) {
    const auto* Lp = static_cast<const int*>(L->p);
    const auto* Li = static_cast<const int*>(L->i);
    const auto* Lnz = static_cast<const int*>(L->nz);
    auto* Lx = static_cast<double*>(L->x);
    cols.slot_rows.resize(static_cast<std::size_t>(n));
    int* const slots_j = cols.slot_rows.data();
    for (std::size_t at = 0; at < places.size(); ++at) {
        const auto slot = static_cast<std::size_t>(places[at]);
        const int j = path_union[slot];
        // The pivot's recurrence, change after change; then each entry of the column
        // takes every change in turn (its arithmetic is that of one change at a time).
        const int begin = Lp[j];
        const int count = column_pivots<0>(cols, j, slot, slots, alpha, shared_parents);
        const int len = Lnz[j] - 1;  // entries below the diagonal
        double* l = Lx + begin + 1;
        // Column j + 1 nests in column j (a supernode: its rows are j's after the
        // first) and is next in the union: after j's first entry (row j + 1, which
        // gives j + 1 its pivots) both columns take their changes row by row, each
        // workspace entry loaded and stored once for both. Every entry gets the same
        // operations in the same order as column after column, so the same bits.
        if (nests_next[static_cast<std::size_t>(j)] && at + 1 < places.size() &&
            static_cast<std::size_t>(places[at + 1]) == slot + 1 && path_union[slot + 1] == j + 1) {
            if (count > 0) cols.apply_entry(l[0], static_cast<int>(slot) + 1, count);
            const int count2 = column_pivots<1>(cols, j + 1, slot + 1, slots, alpha, shared_parents);
            ++at;
            if (count == 0 && count2 == 0) continue;
            const int len2 = len - 1;
            const int* rows_j = Li + begin + 2;
            for (int e = 0; e < len2; ++e) slots_j[e] = slot_of[static_cast<std::size_t>(rows_j[e])];
            double* l2 = Lx + Lp[j + 1] + 1;
            if (count > 0 && count == count2 && std::equal(cols.step_w, cols.step_w + count, cols.step_w2)) {
                cols.apply_pair(l + 1, l2, slots_j, len2, count);
                continue;
            }
            // Different changes in the two columns (another child of j + 1 brings its
            // own): column after column, the second column's coefficients moved into
            // the first's arrays, which the single-column kernels read.
            if (count > 0) cols.apply_column(l + 1, slots_j, len2, count);
            if (count2 > 0) {
                std::copy(cols.step_p2, cols.step_p2 + count2, cols.step_p);
                std::copy(cols.step_beta2, cols.step_beta2 + count2, cols.step_beta);
                std::copy(cols.step_w2, cols.step_w2 + count2, cols.step_w);
                cols.apply_column(l2, slots_j, len2, count2);
            }
            continue;
        }
        if (count == 0 || len == 0) continue;
        const int* rows_j = Li + begin + 1;
        for (int e = 0; e < len; ++e) slots_j[e] = slot_of[static_cast<std::size_t>(rows_j[e])];
        cols.apply_column(l, slots_j, len, count);
    }
}

void CholmodUpdatedFactor::Impl::sweep(std::span<const std::pair<int, int>> rows, std::size_t n_up) {
    const auto un = static_cast<std::size_t>(n);
    if (on_path.size() != un) {
        on_path.assign(un, 0);
        union_bits.assign((un + 63) / 64, 0);
        slot_of.assign(un, 0);
    }
    if (etree.size() != un) find_etree();
    auto parent = [&](int j) { return etree[static_cast<std::size_t>(j)]; };
    const int threads = kernel_threads();
    while (static_cast<int>(workers.size()) < threads) workers.push_back(workers.front());
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
        // The places grouped by subtree (ascending within each), the top's last (group `parts`).
        const auto group_of = [&](int j) {
            const int g = part[static_cast<std::size_t>(j)];
            return static_cast<std::size_t>(g < 0 ? parts : g);
        };
        const auto groups = static_cast<std::size_t>(parts) + 1;
        part_start.assign(groups + 1, 0);
        for (const int j : path_union) ++part_start[group_of(j) + 1];
        for (std::size_t g = 1; g <= groups; ++g) part_start[g] += part_start[g - 1];
        order.resize(slots);
        {
            std::vector<int>& next = workers.front().slot_rows;  // scratch until the columns run
            next.assign(part_start.begin(), part_start.end() - 1);
            for (std::size_t k = 0; k < slots; ++k)
                order[static_cast<std::size_t>(next[group_of(path_union[k])]++)] = static_cast<int>(k);
        }
        const auto top_count = static_cast<std::size_t>(part_start[groups] - part_start[groups - 1]);
        const auto subtree_places = static_cast<long>(slots - top_count);
        if (threads > 1 && subtree_places >= static_cast<long>(kThreadedLoopMin / 4)) {
            // The subtrees side by side (each on one thread), then the top.
            ++counts.subtree_passes;
#pragma omp parallel for schedule(dynamic, 1)
            for (int g = 0; g < parts; ++g) {
                const int from = part_start[static_cast<std::size_t>(g)], to = part_start[static_cast<std::size_t>(g) + 1];
                if (from == to) continue;
                sweep_places(workers[static_cast<std::size_t>(omp_get_thread_num())],
                             std::span<const int>(order).subspan(static_cast<std::size_t>(from), static_cast<std::size_t>(to - from)),
                             slots, alpha, true);
            }
            sweep_places(workers.front(), std::span<const int>(order).subspan(static_cast<std::size_t>(subtree_places)),
                         slots, alpha, false);
        } else {
            for (std::size_t k = 0; k < slots; ++k) order[k] = static_cast<int>(k);
            sweep_places(workers.front(), order, slots, alpha, false);
        }
    }
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
        nests_next[static_cast<std::size_t>(j)] =
            std::equal(Li + Lp[j] + 2, Li + Lp[j] + 1 + len, Li + Lp[j + 1] + 1);
    }
    // Subtree sizes (a parent comes after its children), then the subtrees from the top down.
    std::vector<int> size(static_cast<std::size_t>(n), 1);
    for (int j = 0; j < n; ++j)
        if (const int up = etree[static_cast<std::size_t>(j)]; up >= 0)
            size[static_cast<std::size_t>(up)] += size[static_cast<std::size_t>(j)];
    const int most = std::max(n / kSubtreeShare, kSubtreeMin);
    part.assign(static_cast<std::size_t>(n), -1);
    parts = 0;
    for (int j = n - 1; j >= 0; --j) {
        const auto uj = static_cast<std::size_t>(j);
        if (size[uj] > most) continue;
        const int up = etree[uj];
        part[uj] = up >= 0 && part[static_cast<std::size_t>(up)] >= 0 ? part[static_cast<std::size_t>(up)] : parts++;
    }
    // Each subtree's columns (and the top's, group `parts`), ascending; the subtrees' roots.
    const auto group_of = [&](int j) {
        const int g = part[static_cast<std::size_t>(j)];
        return static_cast<std::size_t>(g < 0 ? parts : g);
    };
    const auto groups = static_cast<std::size_t>(parts) + 1;
    part_column_start.assign(groups + 1, 0);
    for (int j = 0; j < n; ++j) ++part_column_start[group_of(j) + 1];
    for (std::size_t g = 1; g <= groups; ++g) part_column_start[g] += part_column_start[g - 1];
    part_columns.resize(static_cast<std::size_t>(n));
    std::vector<int> root(static_cast<std::size_t>(parts), -1), next(part_column_start.begin(), part_column_start.end() - 1);
    for (int j = 0; j < n; ++j) {
        const std::size_t g = group_of(j);
        part_columns[static_cast<std::size_t>(next[g]++)] = j;
        if (g < static_cast<std::size_t>(parts)) root[g] = j;  // the largest column of a subtree is its root
    }
    // Where each column's rows leave its subtree.
    tail.resize(static_cast<std::size_t>(n));
    top_and_tails.clear();
    for (int j = 0; j < n; ++j) {
        const int first = Lp[j] + 1, end = Lp[j] + Lnz[j];
        const int g = part[static_cast<std::size_t>(j)];
        const int at = g < 0 ? first
                             : static_cast<int>(std::upper_bound(Li + first, Li + end, root[static_cast<std::size_t>(g)]) - Li);
        tail[static_cast<std::size_t>(j)] = at;
        if (at < end) top_and_tails.push_back(j);
    }
}

} // namespace jamsim::linalg
