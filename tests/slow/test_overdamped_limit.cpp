// Paper V: the massive CD model stands in for CD0 in the overdamped limit. At φ = 0.80,
// γ̇ = 1e-3, N = 128, ⟨p⟩ of CD with m = 0.01 agrees with CD0 (both Heun, small Δt) within
// 3 combined standard errors over 4 seeds. Labelled `slow` (about a minute).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "jamsim/run/replica.hpp"
#include "support/statistics.hpp"

using namespace jamsim;

TEST(OverdampedLimit, SmallMassCdReproducesCd0) {
    std::vector<double> cd, cd0;
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
        ReplicaParams p;
        p.n = 128;
        p.phi = 0.80;
        p.rate = 1e-3;
        p.transient = 0.5;
        p.strain = 2.0;
        p.seed = seed;
        p.integrator = "heun";
        p.model = "CD0";
        p.solver = "eigen";
        p.dt = 0.05;
        cd0.push_back(mean_after(run_replica(p).series, &Sample::pressure, p.transient));
        p.model = "CD";
        p.mass = 0.01;
        p.dt = 0.0025;
        cd.push_back(mean_after(run_replica(p).series, &Sample::pressure, p.transient));
    }
    const auto a = jamsim::testing::mean_and_error(cd0), b = jamsim::testing::mean_and_error(cd);
    std::printf("<p>: CD0 %.4g +- %.2g, CD (m = 0.01) %.4g +- %.2g\n", a.mean, a.error, b.mean, b.error);
    EXPECT_LT(std::abs(a.mean - b.mean), 3 * std::hypot(a.error, b.error));
    EXPECT_LT(a.error, 0.1 * a.mean);
}
