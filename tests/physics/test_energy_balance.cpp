// Energy balance in steady shear: the power put in by the shear, (σ + σ_dis) γ̇ A, equals the
// dissipated power plus dE/dt, whose time average vanishes in steady state. Each seed gives
// one difference ⟨P_in − P_dis⟩ over the steady state; over seeds it must be consistent with
// zero (3 standard errors) and small against P_in. Heun with Δt = 0.1 keeps the O(Δt)
// discretisation bias of the sampled balance below the statistical error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "jamsim/run/replica.hpp"
#include "support/statistics.hpp"

using namespace jamsim;

namespace {
void check_balance(const std::string& model, const std::string& solver) {
    std::vector<double> diff, input;
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
        ReplicaParams p;
        p.model = model;
        p.solver = solver;
        p.integrator = "heun";
        p.dt = 0.1;
        p.n = 128;
        p.phi = 0.80;
        p.rate = 1e-3;
        p.transient = 0.5;
        p.strain = 2.5;
        p.seed = seed;
        const auto r = run_replica(p);
        const double in = mean_after(r.series, &Sample::input_power, p.transient);
        const double out = mean_after(r.series, &Sample::dissipated_power, p.transient);
        diff.push_back(in - out);
        input.push_back(in);
    }
    const auto [m, se] = jamsim::testing::mean_and_error(diff);
    const double in = jamsim::testing::mean_and_error(input).mean;
    std::printf("%s: P_in = %.4g, <P_in - P_dis> = %.3g +- %.2g\n", model.c_str(), in, m, se);
    EXPECT_LT(std::abs(m), 3 * se + 1e-12);
    EXPECT_LT(std::abs(m), 0.03 * in);
    EXPECT_GT(in, 0.0);
}
}  // namespace

TEST(EnergyBalance, Rd0) { check_balance("RD0", "petsc"); }
TEST(EnergyBalance, Cd0) { check_balance("CD0", "eigen"); }
