// Cores lent between the ranks of a node (campaign/core_lending.hpp): who gets the idle
// ranks' threads, against answers worked out by hand.
#include <gtest/gtest.h>

#include <vector>

#include "jamsim/campaign/core_lending.hpp"

namespace jamsim {
namespace {

RankWork running(double priority, int useful = 32) { return {.running = true, .priority = priority, .useful = useful}; }
const RankWork idle{};

TEST(CoreLending, IdleRanksOfANodeLendToItsRunningRank) {
    // One node of 4 ranks x 2 threads, 16 CPUs each may use: rank 2 runs, the rest idle.
    const std::vector<RankCores> cores(4, RankCores{.node = 0, .own = 2, .most = 16});
    EXPECT_EQ(lend_cores(cores, {idle, idle, running(5), idle}), (std::vector<int>{2, 2, 8, 2}));
    // Nobody idle: everyone keeps its own.
    EXPECT_EQ(lend_cores(cores, {running(1), running(2), running(3), running(4)}), (std::vector<int>{2, 2, 2, 2}));
}

TEST(CoreLending, LongestCriticalPathFirstThenLowestRank) {
    const std::vector<RankCores> cores(4, RankCores{.node = 0, .own = 1, .most = 4});
    // Two idle cores, two running ranks that could each use 3 more: the longer path takes both.
    EXPECT_EQ(lend_cores(cores, {running(1), idle, idle, running(9)}), (std::vector<int>{1, 1, 1, 3}));
    // Equal paths: the lower rank first.
    EXPECT_EQ(lend_cores(cores, {running(7), idle, idle, running(7)}), (std::vector<int>{3, 1, 1, 1}));
}

TEST(CoreLending, CappedByTheReplicasBlocksAndTheRanksCpus) {
    const std::vector<RankCores> cores(4, RankCores{.node = 0, .own = 1, .most = 4});
    // Rank 0's replica has 2 blocks: it takes 1 more, the rest goes to rank 3.
    EXPECT_EQ(lend_cores(cores, {running(9, 2), idle, idle, running(1)}), (std::vector<int>{2, 1, 1, 2}));
    // A rank bound to its own cores (most = own) takes nothing.
    std::vector<RankCores> bound = cores;
    bound[0].most = 1;
    EXPECT_EQ(lend_cores(bound, {running(9), idle, idle, running(1)}), (std::vector<int>{1, 1, 1, 3}));
    // A replica of one block (N <= 4096) takes nothing.
    EXPECT_EQ(lend_cores(cores, {running(9, 1), idle, idle, idle}), (std::vector<int>{1, 1, 1, 1}));
    EXPECT_EQ(useful_threads(ThreadScaling::pair_loop, 4096), 1);
    EXPECT_EQ(useful_threads(ThreadScaling::pair_loop, 8192), 2);
    EXPECT_EQ(useful_threads(ThreadScaling::pair_loop, 65536), 16);
    EXPECT_EQ(useful_threads(ThreadScaling::pair_loop, 1 << 20), 32);
}

TEST(CoreLending, NeverAcrossNodes) {
    std::vector<RankCores> cores(4, RankCores{.node = 0, .own = 2, .most = 8});
    cores[2].node = cores[3].node = 2;
    // Node 0's idle rank lends to rank 0; node 2's idle rank has nobody to lend to.
    EXPECT_EQ(lend_cores(cores, {running(1), idle, idle, idle}), (std::vector<int>{4, 2, 2, 2}));
    EXPECT_EQ(lend_cores(cores, {running(1), running(1), idle, idle}), (std::vector<int>{2, 2, 2, 2}));
}

TEST(CoreLending, FirstReplicasSpreadOverNodes) {
    // Two nodes of three ranks (nodes named by their first rank, as gather_rank_cores does).
    std::vector<RankCores> cores(6);
    for (std::size_t r = 0; r < cores.size(); ++r) cores[r].node = r < 3 ? 0 : 3;
    EXPECT_EQ(spread_over_nodes(cores), (std::vector<int>{0, 3, 1, 4, 2, 5}));
    // Ranks placed round-robin (node of rank r = r % 2) and a node of one rank.
    std::vector<RankCores> mixed(5);
    const std::int64_t node[] = {0, 1, 0, 1, 4};
    for (std::size_t r = 0; r < mixed.size(); ++r) mixed[r].node = node[r];
    EXPECT_EQ(spread_over_nodes(mixed), (std::vector<int>{0, 1, 4, 2, 3}));
}

}  // namespace
}  // namespace jamsim
