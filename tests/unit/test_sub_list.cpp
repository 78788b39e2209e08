#include <gtest/gtest.h>

#include "jamsim/core/rng.hpp"
#include "jamsim/neighbor/neighbor_list.hpp"
#include "jamsim/neighbor/sub_list.hpp"
#include "support/configurations.hpp"

using namespace jamsim;
using namespace jamsim::testing;  // random configurations, brute-force pair sets

// Filtered from a list with a larger skin, it holds exactly the pairs within d_ij + its own
// skin, at any strain.
TEST(SubList, ExactlyThePairsWithinItsSkin) {
    for (double gamma : {-0.4, 0.0, 0.3}) {
        System sys = random_configuration(300, 0.84, gamma, 8);
        NeighborList parent(0.3);
        parent.build(sys.particles.x, sys.particles.y, sys.particles.diameter, sys.box);
        SubList sub(0.1);
        EXPECT_TRUE(sub.update(parent, sys.box, sys.particles.x, sys.particles.y));
        const PairSet listed = listed_pairs(sub);
        EXPECT_EQ(listed, pairs_within(sys, 0.1)) << "gamma " << gamma;
        EXPECT_LT(listed.size(), parent.size());  // it is thinner than the parent
    }
}

// Property test of the re-filtering rule: random displacements and strain increments that
// keep the parent valid; whenever update() keeps the sub-list, it must hold every touching
// pair. Both outcomes must occur, so that the test exercises the rule.
TEST(SubList, NoContactMissedWhileKept) {
    System sys = random_configuration(400, 0.85, 0.1, 4, false);
    NeighborList parent(0.3);
    parent.build(sys.particles.x, sys.particles.y, sys.particles.diameter, sys.box);
    SubList start(0.1);
    start.update(parent, sys.box, sys.particles.x, sys.particles.y);
    const RngStream rng(4, 0, RngPurpose::TestConfiguration);
    int kept = 0, refiltered = 0;
    for (std::uint32_t trial = 0; trial < 400; ++trial) {
        const System moved = randomly_moved(sys, rng, trial, 0.08, 0.1, 0.1);
        if (parent.needs_rebuild(moved.particles.x, moved.particles.y, moved.box)) continue;
        SubList sub = start;
        if (sub.update(parent, moved.box, moved.particles.x, moved.particles.y)) {
            ++refiltered;
            EXPECT_EQ(sub.builds(), start.builds() + 1);
        } else {
            ++kept;
            EXPECT_EQ(sub.builds(), start.builds());
        }
        ASSERT_TRUE(lists_every_contact(sub, moved)) << "trial " << trial;
    }
    EXPECT_GT(kept, 20);
    EXPECT_GT(refiltered, 20);
}

// A parent rebuilt since (new pairs, or disks re-sorted) always means a fresh filtering.
TEST(SubList, RefilteredAfterParentRebuild) {
    System sys = random_configuration(100, 0.8, 0.0, 1, false);
    NeighborList parent(0.3);
    parent.build(sys.particles.x, sys.particles.y, sys.particles.diameter, sys.box);
    SubList sub(0.1);
    EXPECT_TRUE(sub.update(parent, sys.box, sys.particles.x, sys.particles.y));
    EXPECT_FALSE(sub.update(parent, sys.box, sys.particles.x, sys.particles.y));
    parent.build(sys.particles.x, sys.particles.y, sys.particles.diameter, sys.box);
    EXPECT_TRUE(sub.update(parent, sys.box, sys.particles.x, sys.particles.y));
    EXPECT_EQ(sub.builds(), 2u);
}
