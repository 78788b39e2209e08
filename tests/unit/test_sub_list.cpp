#include <gtest/gtest.h>

#include <set>
#include <utility>

#include "jamsim/core/rng.hpp"
#include "jamsim/neighbor/neighbor_list.hpp"
#include "jamsim/neighbor/sub_list.hpp"
#include "support/configurations.hpp"

using namespace jamsim;
using jamsim::testing::image_separation;
using jamsim::testing::random_configuration;

namespace {
using PairSet = std::set<std::pair<std::size_t, std::size_t>>;

PairSet listed_pairs(const SubList& list) {
    PairSet s;
    for (std::size_t k = 0; k < list.size(); ++k) {
        const auto i = static_cast<std::size_t>(list.owner()[k]);
        const auto j = static_cast<std::size_t>(list.neighbor()[k]);
        EXPECT_TRUE(s.insert({std::min(i, j), std::max(i, j)}).second) << "pair listed twice";
    }
    return s;
}

/// Pairs with some image closer than `extra` + d_ij (brute force over images).
PairSet pairs_within(const System& s, double extra) {
    PairSet out;
    for (std::size_t i = 0; i < s.particles.size(); ++i)
        for (std::size_t j = i + 1; j < s.particles.size(); ++j)
            for (int m = -2; m <= 2; ++m)
                for (int n = -2; n <= 2; ++n) {
                    const auto r = image_separation(s, i, j, m, n);
                    const double range = 0.5 * (s.particles.diameter[i] + s.particles.diameter[j]) + extra;
                    if (r.rx * r.rx + r.ry * r.ry < range * range) out.insert({i, j});
                }
    return out;
}
} // namespace

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
        System moved = sys;
        const double scale = 0.08 * rng.uniform2(trial, 999)[0];
        for (std::size_t i = 0; i < moved.particles.size(); ++i) {
            const auto u = rng.uniform2(trial, static_cast<std::uint32_t>(i));
            moved.particles.x[i] += scale * (u[0] - 0.5);
            moved.particles.y[i] += scale * (u[1] - 0.5);
        }
        moved.box.set_strain_unwrapped(0.1 + 0.1 * (rng.uniform2(trial, 998)[0] - 0.5));
        if (parent.needs_rebuild(moved.particles.x, moved.particles.y, moved.box)) continue;
        SubList sub = start;
        if (sub.update(parent, moved.box, moved.particles.x, moved.particles.y)) {
            ++refiltered;
            EXPECT_EQ(sub.builds(), start.builds() + 1);
        } else {
            ++kept;
            EXPECT_EQ(sub.builds(), start.builds());
        }
        const PairSet listed = listed_pairs(sub);
        for (const auto& pr : pairs_within(moved, 0.0)) ASSERT_TRUE(listed.count(pr));
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
