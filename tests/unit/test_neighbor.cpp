#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <utility>

#include "jamsim/core/rng.hpp"
#include "jamsim/force/force_field.hpp"
#include "jamsim/neighbor/neighbor_list.hpp"
#include "support/configurations.hpp"

using namespace jamsim;
using jamsim::testing::image_separation;
using jamsim::testing::random_configuration;

namespace {
using PairSet = std::set<std::pair<std::size_t, std::size_t>>;

PairSet listed_pairs(const NeighborList& nl) {
    PairSet s;
    for (std::size_t i = 0; i + 1 < nl.first().size(); ++i)
        for (auto k = nl.first()[i]; k < nl.first()[i + 1]; ++k) {
            const auto j = static_cast<std::size_t>(nl.neighbor()[static_cast<std::size_t>(k)]);
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
                    const double range =
                        0.5 * (s.particles.diameter[i] + s.particles.diameter[j]) + extra;
                    if (r.rx * r.rx + r.ry * r.ry < range * range) out.insert({i, j});
                }
    return out;
}
} // namespace

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
        System moved = sys;
        const double scale = 0.2 * rng.uniform2(trial, 999)[0];
        for (std::size_t i = 0; i < moved.particles.size(); ++i) {
            const auto u = rng.uniform2(trial, static_cast<std::uint32_t>(i));
            moved.particles.x[i] += scale * (u[0] - 0.5);
            moved.particles.y[i] += scale * (u[1] - 0.5);
        }
        moved.box.set_strain_unwrapped(0.1 + 0.3 * (rng.uniform2(trial, 998)[0] - 0.5));
        if (nl.needs_rebuild(moved.particles.x, moved.particles.y, moved.box)) {
            ++rejected;
            continue;
        }
        ++accepted;
        const PairSet listed = listed_pairs(nl);
        for (const auto& pr : pairs_within(moved, 0.0)) ASSERT_TRUE(listed.count(pr));
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
    EXPECT_THROW(nl.build(sys.particles.x, sys.particles.y, sys.particles.diameter, sys.box),
                 std::invalid_argument);
}
