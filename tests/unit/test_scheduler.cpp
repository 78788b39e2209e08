// The farm's scheduler (campaign/scheduler.hpp): its order, its chains, and the
// discrete-event simulation that drives it, against answers worked out by hand.
#include <gtest/gtest.h>

#include <stdexcept>
#include <utility>
#include <vector>

#include "jamsim/campaign/scheduler.hpp"

namespace jamsim {
namespace {

using Pairs = std::vector<std::pair<std::int64_t, std::int64_t>>;
using Before = Scheduler::Before;

std::vector<std::int64_t> all(std::size_t n) {
    std::vector<std::int64_t> q(n);
    for (std::size_t k = 0; k < n; ++k) q[k] = static_cast<std::int64_t>(k);
    return q;
}

std::vector<std::int64_t> take_all(Scheduler& s) {
    std::vector<std::int64_t> order;
    for (std::int64_t id = s.take(); id >= 0; id = s.take()) {
        order.push_back(id);
        s.finished(id, Ended::Done);
    }
    return order;
}

TEST(Scheduler, ChainsNumberedByTheirFirstReplica) {
    // Two ladders, 4 -> 1 -> 3 and 0 -> 2, and replica 5 alone.
    const Chains c = chains_of({-1, 4, 0, 1, -1, -1}, 6);
    ASSERT_EQ(c.members.size(), 3u);
    EXPECT_EQ(c.members[0], (std::vector<std::int64_t>{0, 2}));
    EXPECT_EQ(c.members[1], (std::vector<std::int64_t>{4, 1, 3}));
    EXPECT_EQ(c.members[2], (std::vector<std::int64_t>{5}));
    EXPECT_EQ(c.chain_of, (std::vector<std::int64_t>{0, 1, 0, 1, 1, 2}));
    // Without ladders chain k is replica k (so a shard is id % count, as before chains).
    EXPECT_EQ(chains_of({}, 3).chain_of, (std::vector<std::int64_t>{0, 1, 2}));
    EXPECT_THROW(chains_of({1, 0}, 2), std::invalid_argument);   // a cycle
    EXPECT_THROW(chains_of({-1, 7}, 2), std::invalid_argument);  // not a replica
}

TEST(Scheduler, LongestRemainingChainFirstThenCostThenId) {
    // Replica 1 costs most, but 0 -> 3 -> 4 is the longest chain (3 + 3 + 3 = 9 > 5);
    // replicas 2 and 5 cost the same: the lower id first.
    Scheduler s({3, 5, 4, 3, 3, 4}, {-1, -1, -1, 0, 3, -1}, all(6), std::vector<Before>(6, Before::Open));
    EXPECT_DOUBLE_EQ(s.critical_path(0), 9);
    EXPECT_DOUBLE_EQ(s.critical_path(3), 6);
    EXPECT_EQ(take_all(s), (std::vector<std::int64_t>{0, 3, 1, 2, 5, 4}));
    EXPECT_TRUE(s.idle());
}

TEST(Scheduler, SuccessorsWaitForTheirPredecessor) {
    Scheduler s({1, 1, 1}, {-1, 0, 1}, all(3), std::vector<Before>(3, Before::Open));
    EXPECT_EQ(s.take(), 0);
    EXPECT_EQ(s.take(), -1);  // 1 waits for 0
    EXPECT_TRUE(s.may_become_ready());
    s.finished(0, Ended::Done);
    EXPECT_EQ(s.take(), 1);
    s.finished(1, Ended::Interrupted);  // saved, unfinished: 2 keeps waiting, for nothing now
    EXPECT_EQ(s.take(), -1);
    EXPECT_FALSE(s.may_become_ready());
    EXPECT_EQ(s.queued(), 1);
}

TEST(Scheduler, AFailedPredecessorFailsItsChain) {
    Scheduler s({1, 1, 1, 1}, {-1, 0, 1, -1}, all(4), std::vector<Before>(4, Before::Open));
    EXPECT_EQ(s.take(), 0);
    s.finished(0, Ended::Failed);
    EXPECT_EQ(s.take_failed(), (Pairs{{1, 0}, {2, 1}}));
    EXPECT_TRUE(s.take_failed().empty());
    EXPECT_EQ(take_all(s), (std::vector<std::int64_t>{3}));
}

TEST(Scheduler, StandingBeforeTheRun) {
    const std::vector<std::int64_t> pred{-1, 0, 1};
    Scheduler resumed({1, 1, 1}, pred, {1, 2}, {Before::Done, Before::Open, Before::Open});
    EXPECT_EQ(take_all(resumed), (std::vector<std::int64_t>{1, 2}));
    Scheduler after_failure({1, 1, 1}, pred, {1, 2}, {Before::Failed, Before::Open, Before::Open});
    EXPECT_EQ(after_failure.take_failed(), (Pairs{{1, 0}, {2, 1}}));
    EXPECT_TRUE(after_failure.idle());
    // A predecessor neither done nor queued (another run's): its successor waits.
    Scheduler elsewhere({1, 1, 1}, pred, {2}, std::vector<Before>(3, Before::Open));
    EXPECT_EQ(elsewhere.take(), -1);
    EXPECT_FALSE(elsewhere.may_become_ready());
    EXPECT_THROW(Scheduler({1, 1}, {}, {0, 0}, std::vector<Before>(2, Before::Open)), std::invalid_argument);
}

std::vector<SimulatedReplica> replicas(const std::vector<double>& seconds, double speedup = 1) {
    std::vector<SimulatedReplica> out;
    for (const double s : seconds) out.push_back({.cost = s, .seconds = s, .speedup = speedup});
    return out;
}

// Three chains on 2 workers: A = 3 + 3 + 3 (replicas 0, 3, 4), B = 5 (1), C = 4 (2).
// By hand: t = 0 worker 0 takes A1 (path 9), worker 1 B (5); t = 3 A2 (6) on worker 0;
// t = 5 C on worker 1, to 9; t = 6 A3 on worker 0, to 9. Makespan 9 = the bound
// max(18 / 2, 9), no core idle. (Longest replica first would run B and C first and end at 13.)
TEST(Scheduler, SimulationThreeChainsOnTwoWorkers) {
    const SimulatedRun run = simulate_schedule(replicas({3, 5, 4, 3, 3}), {-1, -1, -1, 0, 3}, 2, 1);
    EXPECT_DOUBLE_EQ(run.makespan, 9);
    EXPECT_DOUBLE_EQ(run.work, 18);
    EXPECT_DOUBLE_EQ(run.critical_path, 9);
    EXPECT_EQ(run.longest_chain, 0);
    EXPECT_DOUBLE_EQ(run.bound, 9);
    EXPECT_DOUBLE_EQ(run.idle_core_seconds, 0);
    EXPECT_EQ(run.chains, 3);
}

// A = 6 + 6 (replicas 0, 3), B = 2 (1), C = 2 (2) on 2 workers: t = 0 A1 and B; t = 2 C;
// t = 4 worker 1 idles (A2 waits for A1); t = 6 A2, to 12. Makespan 12 = the chain; idle
// core-seconds 2 × 12 − 16 = 8.
TEST(Scheduler, SimulationALongChainLeavesACoreIdle) {
    const SimulatedRun run = simulate_schedule(replicas({6, 2, 2, 6}), {-1, -1, -1, 0}, 2, 1);
    EXPECT_DOUBLE_EQ(run.makespan, 12);
    EXPECT_DOUBLE_EQ(run.bound, 12);
    EXPECT_DOUBLE_EQ(run.idle_core_seconds, 8);
}

// The first case on 1 worker of 2 threads, every replica 1.5× faster there: 18 / 1.5 = 12 s;
// the bound is max(18 / 2 cores, 9 / 1.5) = 9; both threads busy throughout.
TEST(Scheduler, SimulationOnThreads) {
    const SimulatedRun run = simulate_schedule(replicas({3, 5, 4, 3, 3}, 1.5), {-1, -1, -1, 0, 3}, 1, 2);
    EXPECT_DOUBLE_EQ(run.makespan, 12);
    EXPECT_DOUBLE_EQ(run.critical_path, 6);
    EXPECT_DOUBLE_EQ(run.bound, 9);
    EXPECT_DOUBLE_EQ(run.idle_core_seconds, 0);
    EXPECT_THROW(simulate_schedule(replicas({1}), {}, 0, 1), std::invalid_argument);
}

TEST(Scheduler, SimulationWithCoresLent) {
    // Two ranks of one thread on one node: A (10 s, N = 65536: 16 blocks) and B (2 s). At 2 s B
    // ends, its rank lends its core, and A's last 8 one-thread seconds take 4: makespan 6.
    std::vector<SimulatedReplica> r = replicas({10, 2});
    for (auto& x : r) x.n = 65536;
    const SimulatedLending one_node{.ranks_per_node = 2, .model = SpeedupModel{.serial_fraction = 0}};
    const SimulatedRun lent = simulate_schedule(r, {}, 2, 1, &one_node);
    EXPECT_DOUBLE_EQ(lent.makespan, 6);
    EXPECT_NEAR(lent.idle_core_seconds, 0, 1e-12);
    EXPECT_DOUBLE_EQ(simulate_schedule(r, {}, 2, 1).makespan, 10);  // without lending
    // With 1 s of A's that threads do not shorten (its samples), A on 2 threads takes
    // 9 / 2 + 1 = 5.5 s: 2/10 of it runs in the first 2 s, the rest in 8/10 · 5.5 = 4.4 s.
    r[0].serial = 1;
    EXPECT_NEAR(simulate_schedule(r, {}, 2, 1, &one_node).makespan, 6.4, 1e-12);
    r[0].serial = 0;
    // Ranks on different nodes lend nothing; nor does a replica of one block (N <= 4096).
    const SimulatedLending own_nodes{.ranks_per_node = 1, .model = SpeedupModel{.serial_fraction = 0}};
    EXPECT_DOUBLE_EQ(simulate_schedule(r, {}, 2, 1, &own_nodes).makespan, 10);
    r[0].n = 2048;
    EXPECT_DOUBLE_EQ(simulate_schedule(r, {}, 2, 1, &one_node).makespan, 10);
}

TEST(Scheduler, AmdahlSpeedupModel) {
    const SpeedupModel model;
    constexpr auto pair = ThreadScaling::pair_loop;
    EXPECT_DOUBLE_EQ(model.fraction(pair, 1024), 1.0);  // loops under 4096 run on one thread
    EXPECT_DOUBLE_EQ(model.speedup(pair, 1024, 16), 1.0);
    EXPECT_DOUBLE_EQ(model.fraction(pair, 16384), 0.21);
    EXPECT_DOUBLE_EQ(model.fraction(pair, 65536), 0.05);
    EXPECT_NEAR(model.fraction(pair, 32768), 0.13, 1e-12);  // halfway in log N
    EXPECT_DOUBLE_EQ(model.fraction(pair, 1 << 20), 0.045);
    EXPECT_NEAR(model.speedup(pair, 65536, 16), 1 / (0.05 + 0.95 / 16), 1e-12);  // 16 blocks: all 16 threads
    EXPECT_DOUBLE_EQ(model.speedup(pair, 65536, 1), 1.0);
    // The pair loop shares out whole blocks: 4 at N = 16384, so 16 threads do what 4 do.
    EXPECT_NEAR(model.speedup(pair, 16384, 16), 1 / (0.21 + 0.79 / 4), 1e-12);
    EXPECT_DOUBLE_EQ(model.speedup(pair, 16384, 16), model.speedup(pair, 16384, 4));
    EXPECT_LT(model.speedup(pair, 16384, 2), model.speedup(pair, 16384, 4));
    EXPECT_DOUBLE_EQ((SpeedupModel{.serial_fraction = 0.5}).speedup(pair, 65536, 2), 1 / 0.75);
    EXPECT_DOUBLE_EQ((SpeedupModel{.serial_fraction = 0.5}).speedup(pair, 1024, 2), 1.0);  // one block
}

TEST(Scheduler, SpeedupModelByKernel) {
    const SpeedupModel model;
    // The minimisers: one fraction at every size from 4096 on.
    EXPECT_DOUBLE_EQ(model.fraction(ThreadScaling::minimiser, 16384), 0.10);
    EXPECT_DOUBLE_EQ(model.fraction(ThreadScaling::minimiser, 1 << 20), 0.10);
    EXPECT_DOUBLE_EQ(model.fraction(ThreadScaling::minimiser, 2048), 1.0);
    EXPECT_NEAR(model.speedup(ThreadScaling::minimiser, 65536, 16), 1 / (0.10 + 0.90 / 16), 1e-12);
    // CD0: its factor runs on one thread, so it gains from 2 threads and no more.
    constexpr auto cd0 = ThreadScaling::contact_solve;
    EXPECT_DOUBLE_EQ(model.fraction(cd0, 16384), 0.45);
    EXPECT_DOUBLE_EQ(model.fraction(cd0, 65536), 0.37);
    EXPECT_DOUBLE_EQ(model.fraction(cd0, 262144), 0.37);
    EXPECT_NEAR(model.speedup(cd0, 65536, 2), 1 / (0.37 + 0.63 / 2), 1e-12);
    EXPECT_DOUBLE_EQ(model.speedup(cd0, 65536, 16), model.speedup(cd0, 65536, 2));
    EXPECT_EQ(useful_threads(cd0, 65536), 2);
    EXPECT_EQ(useful_threads(cd0, 8192), 2);
    EXPECT_EQ(useful_threads(cd0, 4096), 2);  // one block, but its solve takes two threads
    EXPECT_EQ(useful_threads(cd0, 2048), 1);
    // --serial-fraction replaces every table, the caps stay.
    const SpeedupModel one{.serial_fraction = 0};
    EXPECT_DOUBLE_EQ(one.speedup(cd0, 65536, 16), 2.0);
    EXPECT_DOUBLE_EQ(one.speedup(ThreadScaling::minimiser, 65536, 16), 16.0);
}

TEST(Scheduler, CoresAreNotLentToACd0ReplicaPastItsUse) {
    // Two ranks' worth of idle cores on one node: an RD0 replica at N = 65536 takes all 4
    // threads of the node and ends sooner, a CD0 replica of the same cost takes 2.
    std::vector<SimulatedReplica> r(1, SimulatedReplica{.cost = 8, .seconds = 8, .n = 65536});
    const SimulatedLending node{.ranks_per_node = 4, .model = SpeedupModel{.serial_fraction = 0}};
    EXPECT_DOUBLE_EQ(simulate_schedule(r, {}, 4, 1, &node).makespan, 2);
    r[0].kernel = ThreadScaling::contact_solve;
    const SimulatedRun cd0 = simulate_schedule(r, {}, 4, 1, &node);
    EXPECT_DOUBLE_EQ(cd0.makespan, 4);
    EXPECT_NEAR(cd0.idle_core_seconds, 4 * 4 - 4 * 2, 1e-12);  // two cores idle throughout
}

}  // namespace
}  // namespace jamsim
