// RD0 below jamming is Newtonian (thesis §3.2): p/γ̇ and σ/γ̇ reach a rate-independent
// plateau once γ̇ is small enough for the distance to φ_J. Close to φ_J the plateau needs
// much smaller rates, and the same comparison must then detect shear thinning: that second
// case shows the test can fail.
//
// Statistics: each seed is an independent replica; its time average over the steady state
// (strain after the transient) is one sample. The error of the seed mean is the standard
// error over seeds, so correlations inside a run need no modelling. Two rates agree when
// |a − b| < 3 sqrt(se_a² + se_b²) (a 3σ test: 0.3% false alarms for Gaussian means).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "jamsim/run/replica.hpp"
#include "support/statistics.hpp"

using namespace jamsim;

namespace {

using jamsim::testing::Estimate;
Estimate over_seeds(const std::vector<double>& v) { return jamsim::testing::mean_and_error(v); }

struct Rheology {
    Estimate p_over_rate, sigma_over_rate;
};

Rheology measure(double phi, double rate, int seeds, double transient, double measured) {
    std::vector<double> p, s;
    for (int seed = 1; seed <= seeds; ++seed) {
        ReplicaParams params;
        params.n = 256;
        params.phi = phi;
        params.rate = rate;
        params.transient = transient;
        params.strain = transient + measured;
        params.sample_interval = 0.01;
        params.seed = static_cast<std::uint64_t>(seed);
        const auto r = run_replica(params);
        p.push_back(mean_after(r.series, &Sample::pressure, transient) / rate);
        s.push_back(mean_after(r.series, &Sample::shear_stress, transient) / rate);
    }
    const Rheology out{over_seeds(p), over_seeds(s)};
    std::printf("phi %.2f rate %.0e: p/rate = %.4g +- %.2g, sigma/rate = %.4g +- %.2g\n", phi, rate,
                out.p_over_rate.mean, out.p_over_rate.error, out.sigma_over_rate.mean, out.sigma_over_rate.error);
    return out;
}

double z_score(Estimate a, Estimate b) {
    return std::abs(a.mean - b.mean) / std::sqrt(a.error * a.error + b.error * b.error);
}

}  // namespace

TEST(Rd0Rheology, NewtonianAtPhi070) {
    const Rheology fast = measure(0.70, 3e-3, 8, 1.0, 4.0);
    const Rheology slow = measure(0.70, 3e-4, 8, 1.0, 4.0);
    // The comparison is only meaningful if the errors are small against the values.
    EXPECT_LT(slow.p_over_rate.error, 0.05 * slow.p_over_rate.mean);
    EXPECT_LT(slow.sigma_over_rate.error, 0.05 * slow.sigma_over_rate.mean);
    EXPECT_LT(z_score(fast.p_over_rate, slow.p_over_rate), 3.0);
    EXPECT_LT(z_score(fast.sigma_over_rate, slow.sigma_over_rate), 3.0);
}

TEST(Rd0Rheology, ShearThinningDetectedAtPhi080) {
    const Rheology fast = measure(0.80, 1e-3, 6, 1.0, 3.0);
    const Rheology slow = measure(0.80, 1e-4, 6, 1.0, 3.0);
    EXPECT_GT(slow.p_over_rate.mean, fast.p_over_rate.mean);
    EXPECT_GT(z_score(fast.p_over_rate, slow.p_over_rate), 3.0);
}
