// The CD0 contact matrix's updated CHOLMOD factor on its own: after every change of the
// contact set (many changes at once, contacts formed outside the factor's pattern after a
// relabelling), its solves must match a dense solve of the current matrix.
#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Dense>
#include <algorithm>
#include <bit>
#include <cstdint>
#include <string>
#include <memory>
#include <cstring>
#include <random>
#include <vector>

#include "../../src/linalg/cholmod_factor.hpp"
#include "jamsim/linalg/contact_solver.hpp"
#include "jamsim/parallel/threads.hpp"

using jamsim::linalg::CholmodUpdatedFactor;
using jamsim::linalg::ContactPair;

namespace {

constexpr double kDelta = 1e-3;

/// Candidate pairs of n points scattered in a periodic unit square: each point with its
/// neighbours closer than `range` (a disk packing's neighbour list, without the physics).
std::vector<ContactPair> neighbour_pairs(int n, double range, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<double> x(static_cast<std::size_t>(n)), y(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        x[static_cast<std::size_t>(i)] = u(rng);
        y[static_cast<std::size_t>(i)] = u(rng);
    }
    std::vector<ContactPair> pairs;
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j) {
            double dx = std::abs(x[static_cast<std::size_t>(i)] - x[static_cast<std::size_t>(j)]);
            double dy = std::abs(y[static_cast<std::size_t>(i)] - y[static_cast<std::size_t>(j)]);
            dx = std::min(dx, 1.0 - dx);
            dy = std::min(dy, 1.0 - dy);
            if (dx * dx + dy * dy < range * range) pairs.push_back({i, j});
        }
    return pairs;
}

/// neighbour_pairs for larger n: the same pairs (in another order), found through a grid of
/// cells of side >= range.
std::vector<ContactPair> binned_neighbour_pairs(int n, double range, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const auto un = static_cast<std::size_t>(n);
    std::vector<double> x(un), y(un);
    for (std::size_t i = 0; i < un; ++i) {
        x[i] = u(rng);
        y[i] = u(rng);
    }
    const int cells = std::max(3, static_cast<int>(1.0 / range));
    std::vector<std::vector<int>> cell(static_cast<std::size_t>(cells * cells));
    const auto cell_of = [&](double v) { return std::min(cells - 1, static_cast<int>(v * cells)); };
    for (int i = 0; i < n; ++i)
        cell[static_cast<std::size_t>(cell_of(x[static_cast<std::size_t>(i)]) * cells +
                                      cell_of(y[static_cast<std::size_t>(i)]))]
            .push_back(i);
    std::vector<ContactPair> pairs;
    for (int i = 0; i < n; ++i) {
        const int cx = cell_of(x[static_cast<std::size_t>(i)]), cy = cell_of(y[static_cast<std::size_t>(i)]);
        for (int ox = -1; ox <= 1; ++ox)
            for (int oy = -1; oy <= 1; ++oy)
                for (const int j :
                     cell[static_cast<std::size_t>(((cx + ox + cells) % cells) * cells + (cy + oy + cells) % cells)]) {
                    if (j <= i) continue;
                    double dx = std::abs(x[static_cast<std::size_t>(i)] - x[static_cast<std::size_t>(j)]);
                    double dy = std::abs(y[static_cast<std::size_t>(i)] - y[static_cast<std::size_t>(j)]);
                    dx = std::min(dx, 1.0 - dx);
                    dy = std::min(dy, 1.0 - dy);
                    if (dx * dx + dy * dy < range * range) pairs.push_back({i, j});
                }
    }
    return pairs;
}

/// The largest deviation of the factor's solve from a dense LDLᵀ solve of A = δ I + the
/// contact Laplacian, relative to the largest velocity, for two random right-hand sides.
double deviation(CholmodUpdatedFactor& factor, int n, std::span<const ContactPair> pairs,
                 std::span<const std::uint8_t> in_contact, std::mt19937_64& rng) {
    Eigen::MatrixXd A = kDelta * Eigen::MatrixXd::Identity(n, n);
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        if (!in_contact[k]) continue;
        const auto i = pairs[k].i, j = pairs[k].j;
        A(i, i) += 1;
        A(j, j) += 1;
        A(i, j) -= 1;
        A(j, i) -= 1;
    }
    std::normal_distribution<double> g;
    std::vector<double> b(2 * static_cast<std::size_t>(n)), x(b.size());
    for (double& v : b) v = g(rng);
    factor.solve(b.data(), x.data());
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(A);
    double worst = 0, scale = 0;
    for (int half = 0; half < 2; ++half) {
        const Eigen::VectorXd rhs = Eigen::Map<const Eigen::VectorXd>(b.data() + half * n, n);
        const Eigen::VectorXd exact = ldlt.solve(rhs);
        for (int i = 0; i < n; ++i) {
            worst = std::max(worst, std::abs(x[static_cast<std::size_t>(half * n + i)] - exact[i]));
            scale = std::max(scale, std::abs(exact[i]));
        }
    }
    return worst / scale;
}

}  // namespace

// Many contacts formed and broken per step (more than one pass of the sweep holds), through
// a relabelling that renumbers the rows and adds candidate pairs outside the factor's
// pattern: every solve matches the dense one. The tolerance: A's condition number is at most
// (2 z_max + δ)/δ ≈ 3e4 here, so a backward-stable factor gives ~1e4 ε ≈ 1e-12; updates
// add round-off growing with their number, far below 1e-8.
TEST(CholmodFactor, UpdatedFactorMatchesDenseSolve) {
    for (const auto ordering : {CholmodUpdatedFactor::Ordering::metis, CholmodUpdatedFactor::Ordering::amd}) {
        std::mt19937_64 rng(11);
        const int n = 300;
        std::vector<ContactPair> pairs = neighbour_pairs(n, 0.09, rng);
        std::vector<std::int32_t> labels(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) labels[static_cast<std::size_t>(i)] = i;
        std::vector<std::uint8_t> in_contact(pairs.size());
        std::bernoulli_distribution half(0.5);
        for (auto& c : in_contact) c = half(rng);
        CholmodUpdatedFactor factor(static_cast<std::size_t>(n), kDelta, ordering);
        factor.adopt(pairs, labels);
        factor.factorize(pairs, in_contact);
        EXPECT_LT(deviation(factor, n, pairs, in_contact, rng), 1e-8);
        double worst = 0;
        int largest_step = 0;
        for (int step = 0; step < 40; ++step) {
            if (step == 20) {
                // A list rebuild: rows renumbered (each pair keeps its disks), and new candidate
                // pairs between distant disks, which the factor's pattern does not hold.
                std::vector<std::int32_t> order(static_cast<std::size_t>(n));
                for (int i = 0; i < n; ++i) order[static_cast<std::size_t>(i)] = i;
                std::shuffle(order.begin(), order.end(), rng);  // new row of old row r: order[r]
                std::vector<std::int32_t> new_labels(static_cast<std::size_t>(n));
                for (int r = 0; r < n; ++r)
                    new_labels[static_cast<std::size_t>(order[static_cast<std::size_t>(r)])] =
                        labels[static_cast<std::size_t>(r)];
                for (auto& p : pairs) p = {order[static_cast<std::size_t>(p.i)], order[static_cast<std::size_t>(p.j)]};
                std::uniform_int_distribution<int> any(0, n - 1);
                auto listed = [&](int i, int j) {  // a neighbour list holds each pair once
                    return std::any_of(pairs.begin(), pairs.end(), [&](const ContactPair& p) {
                        return (p.i == i && p.j == j) || (p.i == j && p.j == i);
                    });
                };
                for (int extra = 0; extra < 30; ++extra) {
                    const int i = any(rng), j = any(rng);
                    if (i != j && !listed(i, j)) {
                        pairs.push_back({i, j});
                        in_contact.push_back(0);
                    }
                }
                labels = new_labels;
                ASSERT_TRUE(factor.adopt(pairs, labels)) << "the factor was not carried over";
            }
            // Flip a random share of the pairs: up to ~90 changes, several sweep passes.
            std::bernoulli_distribution flip(step % 3 == 0 ? 0.08 : 0.01);
            int changes = 0;
            for (auto& c : in_contact)
                if (flip(rng)) {
                    c = !c;
                    ++changes;
                }
            largest_step = std::max(largest_step, changes);
            EXPECT_EQ(factor.follow(pairs, in_contact), changes);
            worst = std::max(worst, deviation(factor, n, pairs, in_contact, rng));
        }
        EXPECT_LT(worst, 1e-8);
        EXPECT_GT(largest_step, 64) << "no step needed several passes of the sweep";
        const auto counts = factor.counts();
        EXPECT_GT(counts.swept, 500);
        EXPECT_GT(counts.filled, 0) << "no contact formed outside the factor's pattern";
    }
}

// The same inputs give the same bits (no threads, fixed order of every sum).
TEST(CholmodFactor, UpdatesAndSolvesAreBitwiseReproducible) {
    auto run = [] {
        std::mt19937_64 rng(5);
        const int n = 200;
        const std::vector<ContactPair> pairs = neighbour_pairs(n, 0.1, rng);
        std::vector<std::int32_t> labels(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) labels[static_cast<std::size_t>(i)] = i;
        std::vector<std::uint8_t> in_contact(pairs.size(), 0);
        CholmodUpdatedFactor factor(static_cast<std::size_t>(n), kDelta, CholmodUpdatedFactor::Ordering::metis);
        factor.adopt(pairs, labels);
        factor.factorize(pairs, in_contact);
        std::bernoulli_distribution flip(0.05);
        for (int step = 0; step < 10; ++step) {
            for (auto& c : in_contact)
                if (flip(rng)) c = !c;
            factor.follow(pairs, in_contact);
        }
        std::vector<double> b(2 * static_cast<std::size_t>(n)), x(b.size());
        std::normal_distribution<double> g;
        for (double& v : b) v = g(rng);
        factor.solve(b.data(), x.data());
        return x;
    };
    EXPECT_EQ(run(), run());
}

// The update's kernels for consecutive rows (the dense separators at the top of the tree and
// the runs of consecutive rows in other columns) on AVX2 or AVX-512 vectors give the bits of
// the x86-64 baseline's (SSE2) kernels: the same element-wise operations in the same order,
// no FMA. Factors with each width the processor has follow the same contact changes (several
// hundred per step, over many steps) beside one with the baseline's; every solve must agree
// bit for bit. 1500 points with about six neighbours each: the top separators have dozens of
// columns, so whole blocks of the wide kernels run (counted).
TEST(CholmodFactor, WideVectorKernelsGiveTheBaselineBits) {
    using Vectors = CholmodUpdatedFactor::Vectors;
    const int n = 1500;
    CholmodUpdatedFactor baseline(static_cast<std::size_t>(n), kDelta, CholmodUpdatedFactor::Ordering::metis,
                                  Vectors::sse2);
    ASSERT_STREQ(baseline.vector_kernels(), "sse2");
    std::vector<std::unique_ptr<CholmodUpdatedFactor>> wide;
    for (const Vectors v : {Vectors::best, Vectors::avx2}) {
        auto f = std::make_unique<CholmodUpdatedFactor>(static_cast<std::size_t>(n), kDelta,
                                                        CholmodUpdatedFactor::Ordering::metis, v);
        const std::string name = f->vector_kernels();
        if (name == "sse2") continue;
        if (std::any_of(wide.begin(), wide.end(), [&](const auto& g) { return name == g->vector_kernels(); })) continue;
        wide.push_back(std::move(f));
    }
    if (wide.empty()) GTEST_SKIP() << "this processor has neither AVX2 nor AVX-512";
    std::mt19937_64 rng(17);
    const std::vector<ContactPair> pairs = neighbour_pairs(n, 0.036, rng);
    std::vector<std::int32_t> labels(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) labels[static_cast<std::size_t>(i)] = i;
    std::vector<std::uint8_t> in_contact(pairs.size());
    std::bernoulli_distribution half(0.5);
    for (auto& c : in_contact) c = half(rng);
    baseline.adopt(pairs, labels);
    baseline.factorize(pairs, in_contact);
    for (auto& f : wide) {
        f->adopt(pairs, labels);
        f->factorize(pairs, in_contact);
    }
    std::normal_distribution<double> g;
    std::vector<double> b(2 * static_cast<std::size_t>(n)), x_wide(b.size()), x_base(b.size());
    std::vector<int> differing_steps(wide.size(), 0);
    for (int step = 0; step < 30; ++step) {
        std::bernoulli_distribution flip(step % 2 == 0 ? 0.03 : 0.005);
        for (auto& c : in_contact)
            if (flip(rng)) c = !c;
        const int changes = baseline.follow(pairs, in_contact);
        for (double& v : b) v = g(rng);
        baseline.solve(b.data(), x_base.data());
        for (std::size_t k = 0; k < wide.size(); ++k) {
            ASSERT_EQ(wide[k]->follow(pairs, in_contact), changes);
            wide[k]->solve(b.data(), x_wide.data());
            differing_steps[k] += std::memcmp(x_wide.data(), x_base.data(), b.size() * sizeof(double)) != 0;
        }
    }
    for (std::size_t k = 0; k < wide.size(); ++k) {
        SCOPED_TRACE(wide[k]->vector_kernels());
        EXPECT_EQ(differing_steps[k], 0);
        // The wide kernels ran on whole blocks.
        EXPECT_GT(wide[k]->counts().block_updates, 10000);
        EXPECT_EQ(wide[k]->counts().refactored, 0);
    }
}

// On several threads the factor splits its elimination tree into two groups of subtrees and a
// top: follow sweeps the groups side by side, solve and follow_and_solve split their passes
// over L along it. The factor must give the one-thread bits on 2, 3 and 4 threads
// (oversubscribed here), through fresh factors, many changes per step (more than one sweep
// pass), a relabelling that adds candidate pairs outside the pattern (fill, which changes the
// tree), and few changes. 8192 points: n reaches the threaded paths (both counted).
TEST(CholmodFactor, UpdatesAndSolvesGiveTheSameBitsOnAnyThreadCount) {
    const int n = 8192;
    std::mt19937_64 pattern_rng(23);
    const std::vector<ContactPair> pairs = binned_neighbour_pairs(n, 0.015, pattern_rng);
    std::vector<ContactPair> second = binned_neighbour_pairs(n, 0.015, pattern_rng);  // another list
    std::vector<std::int32_t> labels(static_cast<std::size_t>(n)), relabelled(labels.size());
    for (int i = 0; i < n; ++i) {
        labels[static_cast<std::size_t>(i)] = i;
        relabelled[static_cast<std::size_t>(i)] = (i * 7919) % n;  // 7919 is prime to 2^13
    }
    struct Outcome {
        std::vector<double> solutions;
        long split_solves = 0, split_steps = 0;
    };
    const auto run = [&](int threads) {
        const int before = jamsim::kernel_threads();
        jamsim::set_kernel_threads(threads);
        std::mt19937_64 rng(29);
        CholmodUpdatedFactor factor(static_cast<std::size_t>(n), kDelta, CholmodUpdatedFactor::Ordering::metis);
        std::vector<std::uint8_t> in_contact(pairs.size());
        std::bernoulli_distribution half(0.5);
        for (auto& c : in_contact) c = half(rng);
        factor.adopt(pairs, labels);
        factor.factorize(pairs, in_contact);
        Outcome out;
        std::normal_distribution<double> g;
        std::vector<double> b(2 * static_cast<std::size_t>(n)), x(b.size());
        int steps = 0;
        const auto step = [&](std::span<const ContactPair> list, double p) {
            std::bernoulli_distribution flip(p);
            for (auto& c : in_contact)
                if (flip(rng)) c = !c;
            for (double& v : b) v = g(rng);
            if (++steps % 2 == 0) {  // follow then solve
                factor.follow(list, in_contact);
                factor.solve(b.data(), x.data());
            } else {  // both at once: on several threads one split step
                factor.follow_and_solve(list, in_contact, b.data(), b.data() + n, x.data(), x.data() + n);
            }
            out.solutions.insert(out.solutions.end(), x.begin(), x.end());
        };
        for (int s = 0; s < 4; ++s) step(pairs, s % 2 == 0 ? 0.02 : 0.002);
        in_contact.assign(second.size(), 0);
        if (!factor.adopt(second, relabelled)) factor.factorize(second, in_contact);
        for (int s = 0; s < 4; ++s) step(second, s < 2 ? 0.01 : 0.0005);
        out.split_solves = factor.counts().split_solves;
        out.split_steps = factor.counts().split_steps;
        jamsim::set_kernel_threads(before);
        return out;
    };
    const Outcome one = run(1);
    EXPECT_EQ(one.split_solves, 0);
    EXPECT_EQ(one.split_steps, 0);
    // 2 to 4 threads, and 2 threads asked for inside a parallel region that allows no nested
    // one: the factor's regions then get a team of one thread, which must take every part.
    const auto run_in_team_of_one = [&] {
        Outcome out;
        const int levels = omp_get_max_active_levels();
        omp_set_max_active_levels(1);
#pragma omp parallel num_threads(2)
#pragma omp single
        out = run(2);
        omp_set_max_active_levels(levels);
        return out;
    };
    for (const int t : {2, 3, 4, 0}) {
        SCOPED_TRACE(t > 0 ? "threads " + std::to_string(t) : std::string("a team of one"));
        const Outcome many = t > 0 ? run(t) : run_in_team_of_one();
        EXPECT_GT(many.split_solves, 0);
        EXPECT_GT(many.split_steps, 0);
        ASSERT_EQ(one.solutions.size(), many.solutions.size());
        EXPECT_EQ(std::memcmp(one.solutions.data(), many.solutions.data(), one.solutions.size() * sizeof(double)), 0);
    }
}

// A downdate that loses positive definiteness (a substrate drag δ near round-off, contacts
// breaking by the hundred) marks the sweep failed and the factor starts afresh. When both
// subtree groups fail in one split step, both flags must be taken and cleared: a flag left
// behind would start the next step afresh where one thread does not. The thread count
// changes between steps (2, 1, 3, 1, ...); the solutions and the fresh starts must be one
// thread's throughout.
TEST(CholmodFactor, FailedDowndatesGiveTheOneThreadBitsWhenThreadsChange) {
    const int n = 8192;
    std::mt19937_64 pattern_rng(37);
    const std::vector<ContactPair> pairs = binned_neighbour_pairs(n, 0.015, pattern_rng);
    std::vector<std::int32_t> labels(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) labels[static_cast<std::size_t>(i)] = i;
    struct Outcome {
        std::vector<double> solutions;
        long refactored = 0, split_steps = 0;
    };
    const auto run = [&](bool changing) {
        const int before = jamsim::kernel_threads();
        std::mt19937_64 rng(41);
        CholmodUpdatedFactor factor(static_cast<std::size_t>(n), 1e-15, CholmodUpdatedFactor::Ordering::metis);
        std::vector<std::uint8_t> in_contact(pairs.size(), 1);
        factor.adopt(pairs, labels);
        factor.factorize(pairs, in_contact);
        Outcome out;
        std::normal_distribution<double> g;
        std::uniform_int_distribution<int> disk(0, n - 1);
        std::bernoulli_distribution breaks(0.005);
        std::vector<std::uint8_t> isolated(static_cast<std::size_t>(n));
        std::vector<double> b(2 * static_cast<std::size_t>(n)), x(b.size());
        for (int s = 0; s < 16; ++s) {
            jamsim::set_kernel_threads(changing ? (s % 2 == 1 ? 1 : 2 + s % 4 / 2) : 1);
            // Downdates only: 0.5% of the contacts broken at random, and on every third step
            // every contact of 12 disks anywhere (an isolated disk's pivot falls to δ, below
            // the round-off of the downdates that take it there: both groups fail).
            std::fill(isolated.begin(), isolated.end(), 0);
            if (s % 3 == 0)
                for (int k = 0; k < 12; ++k) isolated[static_cast<std::size_t>(disk(rng))] = 1;
            for (std::size_t k = 0; k < pairs.size(); ++k)
                if (isolated[static_cast<std::size_t>(pairs[k].i)] || isolated[static_cast<std::size_t>(pairs[k].j)] ||
                    breaks(rng))
                    in_contact[k] = 0;
            for (double& v : b) v = g(rng);
            factor.follow_and_solve(pairs, in_contact, b.data(), b.data() + n, x.data(), x.data() + n);
            out.solutions.insert(out.solutions.end(), x.begin(), x.end());
        }
        out.refactored = factor.counts().refactored;
        out.split_steps = factor.counts().split_steps;
        jamsim::set_kernel_threads(before);
        return out;
    };
    const Outcome one = run(false), changing = run(true);
    EXPECT_GT(one.refactored, 1);  // failures happened (and were recovered from) more than once
    EXPECT_GT(changing.split_steps, 0);
    EXPECT_EQ(one.refactored, changing.refactored);
    ASSERT_EQ(one.solutions.size(), changing.solutions.size());
    EXPECT_EQ(std::memcmp(one.solutions.data(), changing.solutions.data(), one.solutions.size() * sizeof(double)), 0);
}

// The residual check splits its two components over two threads: its verdict must be the
// one thread's even at the edge, where one ulp of rtol decides. The edge is found on one
// thread by bisection over the doubles; two threads must agree on both sides of it.
TEST(ContactResidual, SameVerdictOnAnyThreadCountAtTheEdge) {
    const int n = 8192;
    std::mt19937_64 rng(31);
    const std::vector<ContactPair> contacts = binned_neighbour_pairs(n, 0.015, rng);
    std::normal_distribution<double> g;
    std::vector<double> bx(static_cast<std::size_t>(n)), by(bx.size()), ux(bx.size()), uy(bx.size()), scratch;
    for (std::size_t i = 0; i < bx.size(); ++i) {
        bx[i] = g(rng);
        by[i] = 3 * g(rng);  // a larger ‖b_y‖: the edge is set by x, then by y (below)
        ux[i] = g(rng);
        uy[i] = g(rng);
    }
    const auto within = [&](double rtol, int threads) {
        const int before = jamsim::kernel_threads();
        jamsim::set_kernel_threads(threads);
        const bool ok = jamsim::linalg::contact_residual_within(bx, by, ux, uy, kDelta, contacts, rtol, scratch);
        jamsim::set_kernel_threads(before);
        return ok;
    };
    for (int trial = 0; trial < 2; ++trial) {
        if (trial == 1) std::swap(bx, by);  // the other component decides the edge
        // Bisection over the bit patterns of positive doubles (ordered as the doubles are) to
        // two neighbours: within(lo) false, within(hi) true, on one thread.
        const auto as_double = [](std::uint64_t bits) { return std::bit_cast<double>(bits); };
        std::uint64_t lo_bits = std::bit_cast<std::uint64_t>(0.0), hi_bits = std::bit_cast<std::uint64_t>(1e6);
        ASSERT_FALSE(within(as_double(lo_bits), 1));
        ASSERT_TRUE(within(as_double(hi_bits), 1));
        while (hi_bits - lo_bits > 1) {
            const std::uint64_t mid = lo_bits + (hi_bits - lo_bits) / 2;
            (within(as_double(mid), 1) ? hi_bits : lo_bits) = mid;
        }
        const double lo = as_double(lo_bits), hi = as_double(hi_bits);
        // Two threads, and a team of one (a region that allows no nested one), which takes
        // both components itself.
        const auto in_team_of_one = [&](double rtol) {
            bool ok = false;
            const int levels = omp_get_max_active_levels();
            omp_set_max_active_levels(1);
#pragma omp parallel num_threads(2)
#pragma omp single
            ok = within(rtol, 2);
            omp_set_max_active_levels(levels);
            return ok;
        };
        EXPECT_TRUE(within(hi, 2)) << "trial " << trial;
        EXPECT_FALSE(within(lo, 2)) << "trial " << trial;
        EXPECT_TRUE(in_team_of_one(hi)) << "trial " << trial;
        EXPECT_FALSE(in_team_of_one(lo)) << "trial " << trial;
    }
}
