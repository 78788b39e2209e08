// The solves of the updated CD0 factor (cholmod_factor.hpp): x = Pᵀ L⁻ᵀ D⁻¹ L⁻¹ P b for the
// x and y right-hand sides, on one thread or split over two along the elimination tree
// (Impl::split_tree), and follow_and_solve, which runs the last pass of the sweep and the solve
// as one step (one_thread_step; split_step on two threads), the forward pass behind the sweep.
#include <omp.h>

#include <thread>

#include "cholmod_factor_impl.hpp"

namespace jamsim::linalg {

using factor_kernels::load;
using factor_kernels::Pair;
using factor_kernels::ScopeTimer;
using factor_kernels::SplitTail;
using factor_kernels::store;

namespace {

// The paired passes: row r of `y` holds (x, y) as one SIMD pair, so each entry of L is read
// once per pass for both right-hand sides. The single passes (`_one`) do the same operations
// on one half, so give the same bits.

/// y = P b, both halves, rows [from, to).
void permute_in(const cholmod_factor& L, const double* b_x, const double* b_y, double* y, int from, int to) {
    const auto* perm = static_cast<const int*>(L.Perm);
    for (int k = from; k < to; ++k) {
        y[2 * k] = b_x[perm[k]];
        y[2 * k + 1] = b_y[perm[k]];
    }
}

/// u = the rows of y through pinv (row of each disk), disks [from, to): sequential stores and
/// one (x, y) load per disk, where storing through perm wrote two scattered lines per row.
void permute_out(const int* pinv, const double* y, double* u_x, double* u_y, int from, int to) {
    for (int i = from; i < to; ++i) {
        const Pair xi = load(y + 2 * pinv[i]);
        u_x[i] = xi[0];
        u_y[i] = xi[1];
    }
}

}  // namespace

void ForwardPass::run_to(int column) {
    // (No test for a zero y_j: few columns have one, even at φ = 0.80, where the test cost
    // more than it saved; skipping one gives the same bits.)
    const auto [Lp, Li, Lnz, Lx] = columns_of(L);
    for (int j = next; j < column; ++j) {
        const Pair yj = load(y + 2 * j);
        const int begin = Lp[j];
        int end = begin + Lnz[j];
        if (nests && nests[j] && j + 1 < column && (tails.empty() || tails.front().column > j + 1)) {
            // Column j + 1 nests in j (its rows are j's after the first): j's first entry
            // gives y_{j+1}, then both columns row by row, each row's y loaded and stored once
            // for both (j's update before j + 1's, as column after column: the same bits).
            double* at = y + 2 * (j + 1);
            const Pair yj1 = load(at) - Lx[begin + 1] * yj;
            store(at, yj1);
            const int shift = Lp[j + 1] - begin - 1;  // column j + 1's entry on j's row at p: p + shift
            for (int p = begin + 2; p < end; ++p) {
                at = y + 2 * Li[p];
                store(at, (load(at) - Lx[p] * yj) - Lx[p + shift] * yj1);
            }
            ++j;
            continue;
        }
        if (!tails.empty() && tails.front().column == j) {
            end = tails.front().first;
            tails = tails.subspan(1);
        }
        for (int p = begin + 1; p < end; ++p) {
            double* at = y + 2 * Li[p];
            store(at, load(at) - Lx[p] * yj);
        }
    }
    next = std::max(next, column);
}

namespace {

/// L z = y in place for columns [from, to) (with all columns, the forward pass); `nests`:
/// ForwardPass::nests.
void forward_columns(const cholmod_factor& L, const std::uint8_t* nests, double* y, int from, int to) {
    ForwardPass{.L = L, .y = y, .next = from, .nests = nests}.run_to(to);
}

/// forward_columns' updates of the top's rows from group 1's columns (split_tails, ascending
/// columns, so each row takes them in column order).
void forward_tails(const cholmod_factor& L, double* y, std::span<const SplitTail> tails) {
    const auto [Lp, Li, Lnz, Lx] = columns_of(L);
    for (const SplitTail& tail : tails) {
        const Pair yj = load(y + 2 * tail.column);
        for (int p = tail.first; p < tail.end; ++p) {
            double* at = y + 2 * Li[p];
            store(at, load(at) - Lx[p] * yj);
        }
    }
}

/// Lᵀ x = D⁻¹ z in place for columns [from, to), from the last down (those above `to` done),
/// row by row of Lᵀ, each row's D⁻¹ applied as it is reached: the pivot Lx[begin] is then the
/// next entry of the downward stream, where a pass of its own read one scattered cache line
/// per column (0.3 ms of a step at N = 65536). The same operations in the same order per row,
/// so the same bits.
void backward_columns(const cholmod_factor& L, double* y, int from, int to) {
    const auto [Lp, Li, Lnz, Lx] = columns_of(L);
    for (int j = to - 1; j >= from; --j) {
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
}

/// L z = y in place for one right-hand side: forward_columns' operations on one half.
void forward_one(const cholmod_factor& L, double* y) {
    const auto n = static_cast<int>(L.n);
    const auto [Lp, Li, Lnz, Lx] = columns_of(L);
    for (int j = 0; j < n; ++j) {
        const double yj = y[j];
        const int begin = Lp[j], end = begin + Lnz[j];
        for (int p = begin + 1; p < end; ++p) y[Li[p]] = y[Li[p]] - Lx[p] * yj;
    }
}

/// Lᵀ x = D⁻¹ z in place for one right-hand side: backward_columns' operations on one half.
void backward_one(const cholmod_factor& L, double* y) {
    const auto n = static_cast<int>(L.n);
    const auto [Lp, Li, Lnz, Lx] = columns_of(L);
    for (int j = n - 1; j >= 0; --j) {
        const int begin = Lp[j], end = begin + Lnz[j];
        double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
        int p = end;
        for (; p - 4 >= begin + 1; p -= 4) {
            s0 += Lx[p - 1] * y[Li[p - 1]];
            s1 += Lx[p - 2] * y[Li[p - 2]];
            s2 += Lx[p - 3] * y[Li[p - 3]];
            s3 += Lx[p - 4] * y[Li[p - 4]];
        }
        for (; p > begin + 1; --p) s0 += Lx[p - 1] * y[Li[p - 1]];
        y[j] = y[j] / Lx[begin] - ((s0 + s1) + (s2 + s3));
    }
}

/// u = Pᵀ L⁻ᵀ D⁻¹ L⁻¹ P b for one right-hand side, `y` of n its workspace.
void solve_one(const cholmod_factor& L, const int* pinv, const double* b, double* u, double* y) {
    const auto* perm = static_cast<const int*>(L.Perm);
    for (std::size_t k = 0; k < L.n; ++k) y[k] = b[perm[k]];
    forward_one(L, y);
    backward_one(L, y);
    for (std::size_t i = 0; i < L.n; ++i) u[i] = y[pinv[i]];
}

/// A wait's spin: the processor's pause, and past kSpins of them the thread's time slice given
/// up (when the two threads share a core, oversubscribed, each hand-over would else cost one).
inline void pause(int& spins) {
    constexpr int kSpins = 4096;
    if (++spins > kSpins) {
        std::this_thread::yield();
        return;
    }
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

}  // namespace

void CholmodUpdatedFactor::solve(const double* b, double* x) {
    const auto n = static_cast<std::size_t>(impl_->n);
    solve(b, b + n, x, x + n);
}

void CholmodUpdatedFactor::solve(const double* b_x, const double* b_y, double* u_x, double* u_y) {
    // On several threads (and n of at least kThreadedLoopMin) the elimination tree's two
    // subtree groups side by side (split_step); without a split, the two right-hand sides side
    // by side, one per thread, each reading all of L.
    Impl& m = *impl_;
    const ScopeTimer timer(m.counts.solve_seconds, m.timing);
    const int n = m.n;
    m.find_etree_if_stale();
    if (m.split_usable()) {
        ++m.counts.split_solves;
        m.split_step(nullptr, {}, nullptr, b_x, b_y, u_x, u_y);
        return;
    }
    if (two_threads(n)) {
        m.xy.resize(2 * static_cast<std::size_t>(n));
        double* const yx = m.xy.data();
        double* const yy = yx + n;
        ++m.counts.split_solves;
        const TimedRegion timed;
#pragma omp parallel sections num_threads(2)
        {
#pragma omp section
            solve_one(*m.L, m.pinv.data(), b_x, u_x, yx);
#pragma omp section
            solve_one(*m.L, m.pinv.data(), b_y, u_y, yy);
        }
        return;
    }
    m.xy.resize(2 * static_cast<std::size_t>(n));
    permute_in(*m.L, b_x, b_y, m.xy.data(), 0, n);
    forward_columns(*m.L, m.nests_next.data(), m.xy.data(), 0, n);
    backward_columns(*m.L, m.xy.data(), 0, n);
    permute_out(m.pinv.data(), m.xy.data(), u_x, u_y, 0, n);
}

int CholmodUpdatedFactor::follow_and_solve(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                                           const double* b_x, const double* b_y, double* u_x, double* u_y) {
    Impl& m = *impl_;
    m.find_etree_if_stale();
    // Two threads but no split: follow's sweep, then the solve (a right-hand side per thread).
    if (!m.split_usable() && two_threads(m.n)) {
        const int changes = follow(pairs, in_contact);
        solve(b_x, b_y, u_x, u_y);
        return changes;
    }
    std::pair<int, std::size_t> gathered;
    {
        const ScopeTimer timer(m.counts.upkeep_seconds, m.timing);
        gathered = m.gather_changes(pairs, in_contact);
    }
    const auto [changes, n_up] = gathered;
    const std::span<const std::pair<int, int>> rows = m.sweep_rows;
    bool solved = true, split = false;
    if (rows.empty()) {  // nothing to sweep: the solve alone
        solve(b_x, b_y, u_x, u_y);
        return changes;
    }
    {
        // The sweep's passes but the last as in follow; the last one and the solve in one
        // step, timed as upkeep (the solve hides in it).
        const ScopeTimer timer(m.counts.upkeep_seconds, m.timing);
        double alpha[Impl::kSweepRank];
        std::size_t start = 0;
        for (; start + Impl::kSweepRank < rows.size(); start += Impl::kSweepRank)
            m.run_pass(m.plan_pass(rows, n_up, start, alpha), rows, alpha);
        const Impl::Pass last = m.plan_pass(rows, n_up, start, alpha);
        if (m.split_usable()) {
            m.split_step(&last, rows, alpha, b_x, b_y, u_x, u_y);
            split = true;
        } else if (!two_threads(m.n)) {  // one thread: the forward pass behind the sweep too
            double alpha_second[Impl::kSweepRank];
            std::copy(alpha, alpha + last.rank, alpha_second);
            m.xy.resize(2 * static_cast<std::size_t>(m.n));
            m.one_thread_step(&last, rows, alpha, alpha_second, b_x, b_y, m.xy.data());
            permute_out(m.pinv.data(), m.xy.data(), u_x, u_y, 0, m.n);
            m.merge_second_columns();
        } else {  // fill outside the pattern (gather_changes) changed the tree and broke the split
            m.run_pass(last, rows, alpha);
            solved = false;
        }
    }
    if (!solved && !m.columns.failed) solve(b_x, b_y, u_x, u_y);
    if (std::exchange(m.columns.failed, false)) {  // as in follow: start afresh, and solve again
        ++m.counts.refactored;
        factorize(pairs, in_contact);
        solve(b_x, b_y, u_x, u_y);
        return changes;
    }
    if (split) ++m.counts.split_steps;
    return changes;
}

void CholmodUpdatedFactor::Impl::split_step(const Pass* last, std::span<const std::pair<int, int>> rows, double* alpha,
                                            const double* b_x, const double* b_y, double* u_x, double* u_y) {
    // Columns [0, mid) are group 0, [mid, top) group 1, [top, n) the top (split_tree). Rows of
    // a group's column lie in its group or the top, so each thread takes its group's sweep and
    // passes; the top's rows are where they meet:
    //  - forward: a top row takes its updates from group 0's columns, then group 1's (their
    //    `tails`, held back until group 0 is done, then taken by thread 0 while thread 1
    //    sweeps the top), then the top's, each in column order, as in one ascending pass;
    //  - backward: the top first, then both groups side by side, reading the top's rows.
    // Thread 1 also sweeps the top (after both groups' sweeps) and takes the top's passes.
    // (Thread 0 takes all of the tails, as thread 1 has the top's sweep meanwhile: with the
    // tails split by rows between the threads, this step took 4% longer at N = 65536, 7% at
    // 16384.)
    // Every entry gets the same operations in the same order as on one thread: the same bits.
    const int mid = split_mid, top = split_top;
    xy.resize(2 * static_cast<std::size_t>(n));
    double* const y = xy.data();
    const cholmod_factor& F = *L;
    enum : int { kSwept0 = 1, kForward1 = 2, kTails = 4, kBackTop = 8 };
    std::atomic<int> done{0};
    auto mark = [&](int bit) { done.fetch_or(bit, std::memory_order_release); };
    auto wait = [&](int bit) {
        for (int spins = 0; !(done.load(std::memory_order_acquire) & bit);) pause(spins);
    };
    double alpha_second[kSweepRank];  // thread 1's α: its own copy (the threads would share cache lines)
    if (last) std::copy(alpha, alpha + last->rank, alpha_second);
    const TimedRegion timed;  // to the end: merge_second_columns after it takes a few ns
#pragma omp parallel num_threads(2)
    {
        const int thread = omp_get_thread_num();
        const int team = omp_get_num_threads();
        if (team == 1) {  // a team of one (nested or limited OpenMP): one thread's order
            one_thread_step(last, rows, alpha, alpha_second, b_x, b_y, y);
        } else if (thread == 0) {
            // Group 0's sweep first, whole: thread 1 waits for it to sweep the top. (Thread 1,
            // which also takes the top's passes, runs its forward pass behind its sweep.)
            if (last) {
                sweep_group(0, *last, alpha, columns);
                mark(kSwept0);
            }
            permute_in(F, b_x, b_y, y, 0, mid);
            permute_in(F, b_x, b_y, y, top, n);
            forward_columns(F, nests_next.data(), y, 0, mid);
            wait(kForward1);  // the tails' columns final, and their y_j
            forward_tails(F, y, split_tails);
            mark(kTails);
            wait(kBackTop);
            backward_columns(F, y, 0, mid);
        } else {
            permute_in(F, b_x, b_y, y, mid, top);
            ForwardPass forward{.L = F, .y = y, .next = mid, .tails = split_tails, .nests = nests_next.data()};
            if (last) sweep_group(1, *last, alpha_second, second_columns, &forward);
            forward.run_to(top);
            mark(kForward1);
            if (last) {
                wait(kSwept0);
                take_alpha(*last, rows, 0, alpha, alpha_second);
                sweep_group(kTopGroup, *last, alpha_second, second_columns);
            }
            wait(kTails);  // (after group 0's forward pass, so the top's rows are complete)
            forward_columns(F, nests_next.data(), y, top, n);
            backward_columns(F, y, top, n);
            mark(kBackTop);
            backward_columns(F, y, mid, top);
        }
#pragma omp barrier
        const int from = static_cast<int>(static_cast<long>(n) * thread / team);
        const int to = static_cast<int>(static_cast<long>(n) * (thread + 1) / team);
        permute_out(pinv.data(), y, u_x, u_y, from, to);
    }
    if (last) merge_second_columns();
}

void CholmodUpdatedFactor::Impl::one_thread_step(const Pass* last, std::span<const std::pair<int, int>> rows,
                                                 double* alpha, double* alpha_second, const double* b_x,
                                                 const double* b_y, double* y) {
    const cholmod_factor& F = *L;
    permute_in(F, b_x, b_y, y, 0, n);
    ForwardPass forward{.L = F, .y = y, .next = 0, .nests = nests_next.data()};
    if (last) {
        sweep_group(0, *last, alpha, columns, &forward);
        sweep_group(1, *last, alpha_second, second_columns, &forward);
        take_alpha(*last, rows, 1, alpha_second, alpha);
        sweep_group(kTopGroup, *last, alpha, columns, &forward);
    }
    forward.run_to(n);
    backward_columns(F, y, 0, n);
}

}  // namespace jamsim::linalg
