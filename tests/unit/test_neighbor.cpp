#include <gtest/gtest.h>

#include <cmath>

#include "jamsim/core/rng.hpp"
#include "jamsim/force/force_field.hpp"
#include "jamsim/neighbor/neighbor_list.hpp"
#include "support/configurations.hpp"

using namespace jamsim;
using namespace jamsim::testing;  // random configurations, brute-force pair sets

// The list holds exactly the pairs within d_ij + skin, once each, at any strain, through the
// cell path and the all-pairs path, including unwrapped positions.
TEST(NeighborList, ExactlyThePairsWithinRange) {
    for (std::int64_t n : {40, 500})
        for (double gamma : {-0.5, -0.3, -0.02, 0.0, 0.01, 0.25, 0.49}) {
            System sys = random_configuration(n, 0.8, gamma, 21);
            // unwrap some positions by whole cells: the list must not care
            for (std::size_t i = 0; i < sys.particles.size(); i += 3) {
                sys.particles.x[i] += sys.box.side() * static_cast<double>(i % 5) - 2 * sys.box.side();
                sys.particles.y[i] -= sys.box.side() * static_cast<double>(i % 3);
            }
            // coordinates a hair below 0: folding them rounds onto exactly L, i.e. 0 of the
            // next image; binning and image shift must agree on that
            sys.particles.x[1] = -1e-17;
            sys.particles.y[2] = -1e-17;
            sys.particles.x[4] = std::nextafter(sys.box.side(), 0.0) - sys.box.side();
            NeighborList nl(0.3);
            nl.build(sys.particles.x, sys.particles.y, sys.particles.diameter, sys.box);
            System wrapped = sys;
            for (std::size_t i = 0; i < wrapped.particles.size(); ++i)
                wrapped.box.wrap_into_cell(wrapped.particles.x[i], wrapped.particles.y[i]);
            EXPECT_EQ(listed_pairs(nl), pairs_within(wrapped, 0.3)) << "N " << n << " gamma " << gamma;
        }
}

// Property test of the rebuild rule: random displacements and strain increments; whenever
// needs_rebuild() says the list is still good, it must contain every touching pair.
TEST(NeighborList, NoContactMissedWhileListReportedValid) {
    System sys = random_configuration(400, 0.85, 0.1, 4, false);
    NeighborList nl(0.3);
    nl.build(sys.particles.x, sys.particles.y, sys.particles.diameter, sys.box);
    const RngStream rng(4, 0, RngPurpose::TestConfiguration);
    int accepted = 0, rejected = 0;
    for (std::uint32_t trial = 0; trial < 400; ++trial) {
        const System moved = randomly_moved(sys, rng, trial, 0.2, 0.1, 0.3);
        if (nl.needs_rebuild(moved.particles.x, moved.particles.y, moved.box)) {
            ++rejected;
            continue;
        }
        ++accepted;
        ASSERT_TRUE(lists_every_contact(nl, moved)) << "trial " << trial;
    }
    EXPECT_GT(accepted, 20);
    EXPECT_GT(rejected, 20);
}

TEST(NeighborList, RebuildAfterInvalidate) {
    System sys = random_configuration(100, 0.8, 0.0, 1, false);
    NeighborList nl(0.3);
    EXPECT_TRUE(nl.needs_rebuild(sys.particles.x, sys.particles.y, sys.box));
    nl.build(sys.particles.x, sys.particles.y, sys.particles.diameter, sys.box);
    EXPECT_FALSE(nl.needs_rebuild(sys.particles.x, sys.particles.y, sys.box));
    nl.invalidate();
    EXPECT_TRUE(nl.needs_rebuild(sys.particles.x, sys.particles.y, sys.box));
}

TEST(NeighborList, RefusesBoxTooSmallForMinimumImage) {
    System sys = random_configuration(4, 0.8, 0.0, 1, false);
    NeighborList nl(0.3);
    EXPECT_THROW(nl.build(sys.particles.x, sys.particles.y, sys.particles.diameter, sys.box), std::invalid_argument);
}

// A diverged run's positions (not finite) are refused with the disk, its
// position and the reason, instead of indexing outside the cell grid (that crashed with SIGSEGV).
TEST(NeighborList, RefusesPositionsThatDoNotFold) {
    for (double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL}) {
        System sys = random_configuration(500, 0.8, 0.0, 1, false);
        sys.particles.x[7] = bad;
        NeighborList nl(0.3);
        try {
            nl.build(sys.particles.x, sys.particles.y, sys.particles.diameter, sys.box);
            ADD_FAILURE() << "x = " << bad << " was binned";
        } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find("disk 7 is at ("), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("which does not fold into the box"), std::string::npos) << e.what();
        }
    }
}
