// RD0T, RD0 at temperature T (overdamped Langevin under shear), through its registration.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "jamsim/force/force_field.hpp"
#include "jamsim/run/replica.hpp"

using namespace jamsim;

namespace {

ReplicaParams thermal(double temperature, double kd, double rate) {
    ReplicaParams p;
    p.model = "RD0T";
    p.temperature = temperature;
    p.kd = kd;
    p.rate = rate;
    p.dt = 0.1;
    return p;
}

/// N disks on a square grid with spacing 3 d_s: no disk touches another while it diffuses.
System dilute_grid(int side) {
    Particles q;
    q.resize(static_cast<std::size_t>(side * side));
    for (int a = 0; a < side; ++a)
        for (int b = 0; b < side; ++b) {
            const auto i = static_cast<std::size_t>(a * side + b);
            q.x[i] = 3.0 * a + 1.5;
            q.y[i] = 3.0 * b + 1.5;
            q.diameter[i] = i % 2 ? 1.4 : 1.0;
            q.tag[i] = static_cast<std::int32_t>(i);
        }
    return System{std::move(q), Box(3.0 * side)};
}

/// Positions by tag (the force field may reorder disks).
std::vector<double> by_tag(const Particles& q, const std::vector<double>& v) {
    std::vector<double> out(q.size());
    for (std::size_t i = 0; i < q.size(); ++i) out[static_cast<std::size_t>(q.tag[i])] = v[i];
    return out;
}

}  // namespace

// Free disks diffuse with D = T/k_d: each displacement component after time t has mean 0 and
// variance 2 D t. The sample variance over 2N components has relative standard error
// sqrt(2/(2N)) (Gaussian increments), 3.1% for N = 1024; allowed: 4 standard errors. A noise
// that repeated itself between steps would give 100 times the variance after 100 steps, a
// missing factor 2 half of it.
TEST(ThermalRd0, FreeDisksDiffuseWithTOverKd) {
    const ReplicaParams p = thermal(1e-3, 2.0, 0.0);
    System sys = dilute_grid(32);
    const std::size_t n = sys.particles.size();
    const auto x0 = by_tag(sys.particles, sys.particles.x), y0 = by_tag(sys.particles, sys.particles.y);
    ForceField ff(potential::make_soft_sphere(p.alpha), p.skin);
    auto model = model_of(p).make(p, random_key(p));
    const int steps = 100;
    for (int s = 0; s < steps; ++s) {
        const ForceResult f = ff.compute(sys, Tally::Full);
        ASSERT_EQ(f.contacts, 0);
        model->advance(sys, ff, p.dt, p.rate, s);
    }
    const auto x1 = by_tag(sys.particles, sys.particles.x), y1 = by_tag(sys.particles, sys.particles.y);
    double sum = 0, sum2 = 0;
    for (std::size_t t = 0; t < n; ++t)
        for (double d : {x1[t] - x0[t], y1[t] - y0[t]}) {
            sum += d;
            sum2 += d * d;
        }
    const double m = 2.0 * static_cast<double>(n);
    const double expected = 2.0 * p.temperature / p.kd * steps * p.dt;
    const double ratio = sum2 / m / expected;
    const double se = std::sqrt(2.0 / m);
    std::printf("variance / (2 T t / k_d) = %.4f (standard error %.4f), mean %.2e\n", ratio, se, sum / m);
    EXPECT_NEAR(ratio, 1.0, 4.0 * se);
    EXPECT_LT(std::abs(sum / m), 4.0 * std::sqrt(expected / m));
}

// As T → 0, RD0T follows RD0: from the same sheared, jammed state, 100 steps at T = 1e-30
// stay within 1e-9 d_s of RD0's positions (the noise is 1e-16 per step; the rest is the
// round-off of the two ways of writing the same drift).
TEST(ThermalRd0, ZeroTemperatureLimitIsRd0) {
    ReplicaParams p = thermal(1e-30, 1.0, 1e-3);
    p.n = 256;
    p.phi = 0.85;
    ReplicaParams q = p;
    q.model = "RD0";
    System a = initial_system(q), b = a;
    ForceField fa(potential::make_soft_sphere(2.0), p.skin), fb(potential::make_soft_sphere(2.0), p.skin);
    auto rd0 = model_of(q).make(q, random_key(q));
    auto rd0t = model_of(p).make(p, random_key(p));
    double largest = 0;
    for (int s = 0; s < 100; ++s) {
        fa.compute(a);
        fb.compute(b);
        rd0->advance(a, fa, p.dt, p.rate, s);
        rd0t->advance(b, fb, p.dt, p.rate, s);
    }
    const auto xa = by_tag(a.particles, a.particles.x), xb = by_tag(b.particles, b.particles.x);
    for (std::size_t t = 0; t < xa.size(); ++t) largest = std::max(largest, std::abs(xa[t] - xb[t]));
    EXPECT_EQ(a.box.strain(), b.box.strain());
    EXPECT_LT(largest, 1e-9);
    EXPECT_GT(largest, 0.0);  // it is a different integrator, not RD0 under another name
}

// A replica depends only on its parameters and seed: the same run twice is bitwise equal, and
// another seed or temperature changes it.
TEST(ThermalRd0, DeterministicPerSeedAndTemperature) {
    ReplicaParams p = thermal(1e-4, 1.0, 1e-2);
    p.n = 64;
    p.phi = 0.84;
    p.strain = 0.05;
    const auto a = run_replica(p), b = run_replica(p);
    ReplicaParams other_seed = p, other_t = p;
    other_seed.seed = 2;
    other_t.temperature = 2e-4;
    const auto c = run_replica(other_seed), d = run_replica(other_t);
    ASSERT_EQ(a.series.size(), b.series.size());
    for (std::size_t k = 0; k < a.series.size(); ++k) EXPECT_EQ(a.series[k].pressure, b.series[k].pressure);
    EXPECT_NE(a.series[a.series.size() - 1].pressure, c.series[c.series.size() - 1].pressure);
    EXPECT_NE(a.series[a.series.size() - 1].pressure, d.series[d.series.size() - 1].pressure);
}
