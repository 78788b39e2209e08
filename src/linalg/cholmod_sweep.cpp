// The sweep of the updated CD0 factor: a step's contact changes applied to L in place, in one
// pass over the union of their elimination-tree paths (cholmod_factor.hpp, `follow`).
#include "cholmod_factor_impl.hpp"

#include <omp.h>

#include <queue>

namespace jamsim::linalg {

using factor_kernels::ColumnChanges;
using factor_kernels::SweepColumns;

template <int Second>
[[gnu::always_inline]] inline int CholmodUpdatedFactor::Impl::column_pivots(SweepColumns& cols, int j, std::size_t slot,
                                                                            std::size_t slots, double* alpha) {
    double* const ps = Second ? cols.step_p2 : cols.step_p;
    double* const betas = Second ? cols.step_beta2 : cols.step_beta;
    double** const ws = Second ? cols.step_w2 : cols.step_w;
    auto* Lx = static_cast<double*>(L->x);
    const int begin = static_cast<const int*>(L->p)[j];
    const std::uint64_t here = on_path[static_cast<std::size_t>(j)] & ~kVisited;
    on_path[static_cast<std::size_t>(j)] = 0;
    if (const int up = etree[static_cast<std::size_t>(j)]; up >= 0) {
        auto& above = on_path[static_cast<std::size_t>(up)];
        // A subtree's root passes its changes to the top of the tree, whose columns the
        // other subtree's root may reach at the same time (run_pass, split_step).
        if (group_of(up) != group_of(j))
            std::atomic_ref<std::uint64_t>(above).fetch_or(here, std::memory_order_relaxed);
        else
            above |= here;
    }
    int count = 0;
    for (std::uint64_t active = here; active; active &= active - 1) {
        const int t = __builtin_ctzll(active);
        double* wt = w.data() + static_cast<std::size_t>(t) * slots;
        const double p = std::exchange(wt[slot], 0.0);  // read for the last time: zero again (plan_pass)
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

CholmodUpdatedFactor::Impl::Pass CholmodUpdatedFactor::Impl::plan_pass(std::span<const std::pair<int, int>> rows,
                                                                       std::size_t n_up, std::size_t start,
                                                                       double* alpha) {
    const auto un = static_cast<std::size_t>(n);
    if (on_path.size() != un) {
        on_path.assign(un, 0);
        union_bits.assign((un + 63) / 64, 0);
        slot_of.assign(un, 0);
    }
    find_etree_if_stale();
    columns.slot_rows.resize(un);
    second_columns.slot_rows.resize(un);
    auto parent = [&](int j) { return etree[static_cast<std::size_t>(j)]; };
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
    // The workspace holds only the rows of the union (every row a change reaches is on its
    // path), in the union's order (slot_of): small enough for the cache, and consecutive rows
    // keep consecutive slots.
    const std::size_t slots = path_union.size();
    for (std::size_t k = 0; k < slots; ++k) slot_of[static_cast<std::size_t>(path_union[k])] = static_cast<int>(k);
    // The workspace is all zeros between passes: a change's column has nonzeros only in the
    // rows of its path, and each column of the path zeroes its row as it takes its pivot
    // (column_pivots), so a pass leaves it as it found it. Zeroing it here was a serial
    // stretch of 0.1 ms per step at N = 65536 (2 MB).
    if (const std::size_t need = static_cast<std::size_t>(rank) * slots; w.size() < need) w.resize(need, 0.0);
    for (int t = 0; t < rank; ++t) {
        const auto [a, b] = rows[start + static_cast<std::size_t>(t)];
        double* wt = w.data() + static_cast<std::size_t>(t) * slots;
        wt[slot_of[static_cast<std::size_t>(a)]] = 1.0;
        wt[slot_of[static_cast<std::size_t>(b)]] = -1.0;
    }
    // The union's places by group of their columns (split_tree). A subtree group's columns
    // hold only the changes that start in it and reach only its own columns and the top's
    // workspace rows of those changes, so the two groups can run side by side and the top
    // after both. Every column gets the same operations in the same order as in one
    // ascending pass: the same bits.
    for (auto& list : group_slots) list.clear();
    for (std::size_t k = 0; k < slots; ++k) group_slots[group_of(path_union[k])].push_back(static_cast<int>(k));
    return Pass{start, rank, slots};
}

void CholmodUpdatedFactor::Impl::take_alpha(const Pass& pass, std::span<const std::pair<int, int>> rows, int group,
                                            const double* from, double* to) const {
    for (int t = 0; t < pass.rank; ++t)
        if (group_of(rows[pass.start + static_cast<std::size_t>(t)].first) == group) to[t] = from[t];
}

void CholmodUpdatedFactor::Impl::sweep(std::span<const std::pair<int, int>> rows, std::size_t n_up) {
    double alpha[kSweepRank];
    for (std::size_t start = 0; start < rows.size(); start += kSweepRank)
        run_pass(plan_pass(rows, n_up, start, alpha), rows, alpha);
}

void CholmodUpdatedFactor::Impl::run_pass(const Pass& pass, std::span<const std::pair<int, int>> rows, double* alpha) {
    if (!split_usable()) {
        for (int group = 0; group < 3; ++group) sweep_group(group, pass, alpha, columns);
        return;
    }
    // The second group's changes keep their recurrence's α in a copy of their own (the two
    // threads would otherwise write the same cache lines column after column).
    double alpha_second[kSweepRank];
    std::copy(alpha, alpha + pass.rank, alpha_second);
    {
        const TimedRegion timed;  // the region alone: the top's sweep below is serial
#pragma omp parallel num_threads(2)
        {
            const int thread = omp_get_thread_num();
            const bool alone = omp_get_num_threads() == 1;  // a team of one (nested or limited OpenMP) takes both
            if (thread == 0) sweep_group(0, pass, alpha, columns);
            if (thread == 1 || alone) sweep_group(1, pass, alpha_second, second_columns);
        }
    }
    take_alpha(pass, rows, 1, alpha_second, alpha);
    sweep_group(kTopGroup, pass, alpha, columns);
    merge_second_columns();
}

void CholmodUpdatedFactor::Impl::merge_second_columns() {
    // The second thread's flag always taken (and cleared), even when the first failed too: a
    // flag left set would make the next step start afresh where one thread does not.
    if (std::exchange(second_columns.failed, false)) columns.failed = true;
    columns.block_updates += std::exchange(second_columns.block_updates, 0);
}

void CholmodUpdatedFactor::Impl::sweep_group(int group, const Pass& pass, double* alpha, SweepColumns& cols,
                                             ForwardPass* forward) {
    const std::span<const int> places = group_slots[group];
    for (std::size_t k = 0; k < places.size();) {
        const int j = path_union[static_cast<std::size_t>(places[k])];
        if (forward) forward->run_to(j);
        const int swept = sweep_at(places, k, pass.slots, alpha, cols);
        if (forward) forward->run_to(j + swept);
        k += static_cast<std::size_t>(swept);
    }
}

int CholmodUpdatedFactor::Impl::sweep_at(std::span<const int> places, std::size_t k, std::size_t slots, double* alpha,
                                         SweepColumns& cols) {
    const auto* Lp = static_cast<const int*>(L->p);
    const auto* Li = static_cast<const int*>(L->i);
    const auto* Lnz = static_cast<const int*>(L->nz);
    auto* Lx = static_cast<double*>(L->x);
    const auto slot = static_cast<std::size_t>(places[k]);
    const int j = path_union[slot];
    // The pivot's recurrence, change after change; then each entry of the column
    // takes every change in turn (its arithmetic is that of one change at a time).
    const int begin = Lp[j];
    const int count = column_pivots<0>(cols, j, slot, slots, alpha);
    const int len = Lnz[j] - 1;  // entries below the diagonal
    double* l = Lx + begin + 1;
    // Column j + 1 nests in column j (a supernode: its rows are j's after the
    // first) and is next in the union: after j's first entry (row j + 1, which
    // gives j + 1 its pivots) both columns take their changes row by row, each
    // workspace entry loaded and stored once for both. Every entry gets the same
    // operations in the same order as column after column, so the same bits.
    if (nests_next[static_cast<std::size_t>(j)] && k + 1 < places.size() &&
        static_cast<std::size_t>(places[k + 1]) == slot + 1 && path_union[slot + 1] == j + 1) {
        if (count > 0) cols.apply_entry(l[0], static_cast<int>(slot) + 1, count);
        const int count2 = column_pivots<1>(cols, j + 1, slot + 1, slots, alpha);
        if (count == 0 && count2 == 0) return 2;
        const int len2 = len - 1;
        const int* rows_j = Li + begin + 2;
        int* slots_j = cols.slot_rows.data();
        for (int e = 0; e < len2; ++e) slots_j[e] = slot_of[static_cast<std::size_t>(rows_j[e])];
        double* l2 = Lx + Lp[j + 1] + 1;
        if (count > 0 && count == count2 && std::equal(cols.step_w, cols.step_w + count, cols.step_w2)) {
            cols.apply_pair(l + 1, l2, slots_j, len2, count);
            return 2;
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
        return 2;
    }
    if (count == 0 || len == 0) return 1;
    const int* rows_j = Li + begin + 1;
    int* slots_j = cols.slot_rows.data();
    for (int e = 0; e < len; ++e) slots_j[e] = slot_of[static_cast<std::size_t>(rows_j[e])];
    cols.apply_column(l, slots_j, len, count);
    return 1;
}

void CholmodUpdatedFactor::Impl::find_etree() {
    const auto [Lp, Li, Lnz, Lx] = columns_of(*L);
    etree.resize(static_cast<std::size_t>(n));
    for (int j = 0; j < n; ++j) etree[static_cast<std::size_t>(j)] = Lnz[j] > 1 ? Li[Lp[j] + 1] : -1;
    nests_next.assign(static_cast<std::size_t>(n), 0);
    for (int j = 0; j + 1 < n; ++j) {
        const int len = Lnz[j] - 1;
        if (len < 2 || Li[Lp[j] + 1] != j + 1 || Lnz[j + 1] != len) continue;
        nests_next[static_cast<std::size_t>(j)] = std::equal(Li + Lp[j] + 2, Li + Lp[j] + 1 + len, Li + Lp[j + 1] + 1);
    }
    // The split for two threads: checked again with the tree (find_etree_if_stale); kept when
    // it still holds (fill changes a few columns' parents), its tails found afresh. Steps on
    // one thread check no split, so one kept from before them stays kept.
    split_computed = false;
    if (is_split(split_mid, split_top)) {
        kept_mid = split_mid;
        kept_top = split_top;
    }
    split_mid = split_top = n;
    split_tails.clear();
}

void CholmodUpdatedFactor::Impl::split_tree() {
    split_computed = true;
    split_tails.clear();
    // The split chosen for this L before fill changed its tree, if no parent crosses yet
    // (choosing afresh costs about as much as a step at N = 65536, and fill comes every few
    // dozen steps); else afresh.
    bool holds = is_split(kept_mid, kept_top);
    for (int j = 0; holds && j < kept_mid; ++j) {
        const int up = etree[static_cast<std::size_t>(j)];
        holds = up < kept_mid || up >= kept_top;
    }
    if (holds) {
        split_mid = kept_mid;
        split_top = kept_top;
    } else {
        // Fill joined a subtree of one group to the other: the top still holds every ancestor
        // of the columns below it, so only the groups are chosen again (choosing the top too
        // cost 9 ms at N = 65536, some 40 times in 4000 steps); afresh if no boundary halves them.
        const std::vector<double> own = sweep_shares();
        if (is_split(kept_mid, kept_top)) split_groups(kept_top, own);
        if (!is_split(split_mid, split_top)) choose_split(own);
    }
    if (is_split(split_mid, split_top)) find_split_tails();
}

std::vector<double> CholmodUpdatedFactor::Impl::sweep_shares() const {
    // A column's share of a sweep: its entries times the columns below it (a change starts
    // at any of them alike).
    const auto* Lnz = static_cast<const int*>(L->nz);
    const auto un = static_cast<std::size_t>(n);
    std::vector<double> below(un, 1.0);
    for (std::size_t j = 0; j < un; ++j)
        if (const int up = etree[j]; up >= 0) below[static_cast<std::size_t>(up)] += below[j];
    for (std::size_t j = 0; j < un; ++j) below[j] *= Lnz[j];
    return below;
}

void CholmodUpdatedFactor::Impl::choose_split(std::span<const double> own) {
    const auto un = static_cast<std::size_t>(n);
    split_mid = split_top = n;  // no split: every column in the first group's place (see group_of)
    // A column's share of a sweep (own, sweep_shares); a subtree's, the sum over its columns.
    std::vector<double> subtree(own.begin(), own.end());
    for (std::size_t j = 0; j < un; ++j)
        if (const int up = etree[j]; up >= 0) subtree[static_cast<std::size_t>(up)] += subtree[j];
    std::vector<int> first_child(un + 1, 0), children(un);
    for (std::size_t j = 0; j < un; ++j)
        if (const int up = etree[j]; up >= 0) ++first_child[static_cast<std::size_t>(up) + 1];
    for (std::size_t j = 0; j < un; ++j) first_child[j + 1] += first_child[j];
    {
        std::vector<int> next(first_child.begin(), first_child.end() - 1);
        for (std::size_t j = 0; j < un; ++j)
            if (const int up = etree[j]; up >= 0)
                children[static_cast<std::size_t>(next[static_cast<std::size_t>(up)]++)] = static_cast<int>(j);
    }
    // The top: cut the heaviest subtree (its root to the top, its children in its place)
    // while the estimate top + max(heaviest, half of the rest) falls; the best cut seen. The
    // top is every column from the lowest cut column on (see below), so it is priced so.
    std::vector<double> from_here(un + 1, 0.0);  // Σ own over columns [j, n)
    for (std::size_t j = un; j-- > 0;) from_here[j] = from_here[j + 1] + own[j];
    using Entry = std::pair<double, int>;
    std::priority_queue<Entry> heaviest;
    for (std::size_t j = 0; j < un; ++j)
        if (etree[j] < 0) heaviest.emplace(subtree[j], static_cast<int>(j));
    const double total = from_here[0];
    double best = total;
    int lowest_cut = n, top_from = n;  // the lowest column cut so far, and in the best cut
    while (!heaviest.empty() && heaviest.top().first > (total - from_here[static_cast<std::size_t>(lowest_cut)]) / 64) {
        const int j = heaviest.top().second;
        heaviest.pop();
        lowest_cut = std::min(lowest_cut, j);
        for (int k = first_child[static_cast<std::size_t>(j)]; k < first_child[static_cast<std::size_t>(j) + 1]; ++k) {
            const int child = children[static_cast<std::size_t>(k)];
            heaviest.emplace(subtree[static_cast<std::size_t>(child)], child);
        }
        const double top = from_here[static_cast<std::size_t>(lowest_cut)];
        const double estimate = top + std::max(heaviest.empty() ? 0.0 : heaviest.top().first, (total - top) / 2);
        if (estimate < best) {
            best = estimate;
            top_from = lowest_cut;
        }
    }
    if (top_from == n) return;
    // The top as the columns from the lowest cut column on (postordered: above every
    // subtree below the cut).
    split_groups(top_from, own);
}

void CholmodUpdatedFactor::Impl::split_groups(int top_from, std::span<const double> own) {
    // The groups as the columns below the top, split where no column's parent crosses
    // (postordered: between two subtrees), halving the work (sweep and passes over L, each as
    // a share of its whole). No boundary near the middle: no split.
    const auto* Lnz = static_cast<const int*>(L->nz);
    split_mid = split_top = n;
    const auto k_top = static_cast<std::size_t>(top_from);
    std::vector<int> crossing(k_top + 1, 0);  // boundaries m with some j < m <= parent(j) < top_from
    for (std::size_t j = 0; j < k_top; ++j)
        if (const int up = etree[j]; up >= 0 && up < top_from) {
            ++crossing[j + 1];
            --crossing[static_cast<std::size_t>(up) + 1];
        }
    double sweep_total = 0, entries_total = 0;
    for (std::size_t j = 0; j < k_top; ++j) {
        sweep_total += own[j];
        entries_total += Lnz[j];
    }
    double sweep_below = 0, entries_below = 0, best_gap = 2;
    int inside = 0;
    for (std::size_t m = 1; m < k_top; ++m) {
        sweep_below += own[m - 1];
        entries_below += Lnz[m - 1];
        inside += crossing[m];
        if (inside != 0) continue;
        const double gap = std::abs(sweep_below / sweep_total - 0.5) + std::abs(entries_below / entries_total - 0.5);
        if (gap < best_gap) {
            best_gap = gap;
            split_mid = static_cast<int>(m);
        }
    }
    if (best_gap > 0.5) {
        split_mid = n;
        return;
    }
    split_top = top_from;
}

void CholmodUpdatedFactor::Impl::find_split_tails() {
    // Group 1's columns with entries in the top's rows (near the top of its subtrees): where
    // those entries begin.
    const auto [Lp, Li, Lnz, Lx] = columns_of(*L);
    for (int j = split_mid; j < split_top; ++j) {
        const int begin = Lp[j] + 1, end = Lp[j] + Lnz[j];
        const int first = static_cast<int>(std::lower_bound(Li + begin, Li + end, split_top) - Li);
        if (first < end) split_tails.push_back({j, first, end});
    }
}

}  // namespace jamsim::linalg
