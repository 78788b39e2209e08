#include <gtest/gtest.h>

#include <bit>
#include <cstdint>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "jamsim/force/force_field.hpp"
#include "jamsim/dynamics/rd0.hpp"
#include "jamsim/run/replica.hpp"

using namespace jamsim;

namespace {

ReplicaParams small_run() {
    ReplicaParams p;
    p.n = 128;
    p.phi = 0.84;
    p.rate = 1e-3;
    p.strain = 0.1;
    p.sample_interval = 0.002;
    p.seed = 3;
    return p;
}

/// A sheared state: the replica's random start relaxed by 400 Euler steps under shear, so
/// that the convergence test does not start from the violent random overlaps.
System sheared_start(const ReplicaParams& params) {
    System sys = initial_system(params);
    ForceField ff(potential::make_soft_sphere(params.alpha), params.skin);
    Rd0 model(ReplicaParams{.integrator = "euler", .kd = 1.0});
    for (int s = 0; s < 400; ++s) {
        ff.compute(sys);
        model.advance(sys, ff, 0.2, params.rate, 0);
    }
    return sys;
}

/// Integrate RD0 from `start` for time T with step dt.
System integrate(const ReplicaParams& params, const System& start, double T, double dt, const std::string& integ) {
    System sys = start;
    ForceField ff(potential::make_soft_sphere(params.alpha), params.skin);
    Rd0 model(ReplicaParams{.integrator = integ, .kd = 1.0});
    const auto steps = static_cast<long>(std::llround(T / dt));
    for (long s = 0; s < steps; ++s) {
        ff.compute(sys);
        model.advance(sys, ff, dt, params.rate, 0);
    }
    return sys;
}

/// Largest lab-frame distance between the same particle (by tag) in two states at the same
/// strain; the min image of a small difference is exact.
double max_diff(const System& a, const System& b) {
    std::vector<double> bx(b.particles.size()), by(b.particles.size());
    for (std::size_t k = 0; k < b.particles.size(); ++k) {
        bx[static_cast<std::size_t>(b.particles.tag[k])] = b.particles.x[k];
        by[static_cast<std::size_t>(b.particles.tag[k])] = b.particles.y[k];
    }
    double m = 0.0;
    for (std::size_t k = 0; k < a.particles.size(); ++k) {
        const auto t = static_cast<std::size_t>(a.particles.tag[k]);
        const Vec2 d = a.box.min_image(a.particles.x[k] - bx[t], a.particles.y[k] - by[t]);
        m = std::max(m, std::sqrt(norm2(d)));
    }
    return m;
}

/// Observed order of convergence from errors at dt, dt/2, dt/4 against a dt/64 reference.
std::vector<double> observed_orders(const ReplicaParams& p, const std::string& integ, double dt) {
    const double T = 4.0;
    const System start = sheared_start(p);
    const System ref = integrate(p, start, T, dt / 64, integ);
    std::vector<double> orders;
    double previous = -1;
    for (double h : {dt, dt / 2, dt / 4}) {
        const double e = max_diff(integrate(p, start, T, h, integ), ref);
        std::printf("%s dt %g error %.3e\n", integ.c_str(), h, e);
        if (previous > 0) orders.push_back(std::log2(previous / e));
        previous = e;
    }
    return orders;
}

}  // namespace

TEST(Rd0, SameSeedGivesBitwiseIdenticalTimeSeries) {
    const ReplicaParams p = small_run();
    const auto a = run_replica(p), b = run_replica(p);
    ASSERT_EQ(a.series.size(), b.series.size());
    ASSERT_GT(a.series.size(), 40u);
    for (std::size_t k = 0; k < a.series.size(); ++k)
        for (const auto& c : kSampleColumns)  // bitwise, so NaN (not applicable) equals NaN
            ASSERT_EQ(std::bit_cast<std::uint64_t>(a.series[k].*c.member),
                      std::bit_cast<std::uint64_t>(b.series[k].*c.member))
                << c.name;
    ReplicaParams other = p;
    other.seed = 4;
    const auto c = run_replica(other);
    EXPECT_NE(a.series[10].pressure, c.series[10].pressure);
}

// Heun is second order in Δt, Euler first order. Hertzian contacts (α = 5/2) keep the
// right-hand side C¹ so the asymptotic orders are clean; 128 disks at φ = 0.84 under shear.
TEST(Rd0, HeunIsSecondOrderEulerFirstOrder) {
    ReplicaParams p = small_run();
    p.alpha = 2.5;
    for (double order : observed_orders(p, "heun", 0.1)) {
        EXPECT_GT(order, 1.8);
        EXPECT_LT(order, 2.3);
    }
    for (double order : observed_orders(p, "euler", 0.1)) {
        EXPECT_GT(order, 0.85);
        EXPECT_LT(order, 1.2);
    }
}

// Overdamped dynamics at zero shear is a gradient flow: the energy never increases
// (for Δt below the stability limit).
TEST(Rd0, EnergyDecreasesWithoutShear) {
    ReplicaParams p = small_run();
    p.rate = 0.0;
    p.time = 200.0;
    p.sample_interval = 1.0;
    const auto r = run_replica(p);
    for (std::size_t k = 1; k < r.series.size(); ++k)
        ASSERT_LE(r.series[k].energy_per_particle, r.series[k - 1].energy_per_particle);
    EXPECT_LT(r.series[r.series.size() - 1].energy_per_particle, 0.1 * r.series[0].energy_per_particle);
}

// The non-affine velocity of RD0 is f/k_d, so at rate 0 its mean square is (1/N) Σ |f|².
TEST(Rd0, NonaffineVelocityIsForceOverKd) {
    ReplicaParams p = small_run();
    p.kd = 2.0;
    System sys = initial_system(p);
    ForceField ff(potential::make_soft_sphere(2.0), 0.3);
    ff.compute(sys);
    Rd0 model(ReplicaParams{.integrator = "euler", .kd = 2.0});
    double sum = 0;
    for (std::size_t i = 0; i < sys.particles.size(); ++i)
        sum += std::pow(sys.particles.fx[i], 2) + std::pow(sys.particles.fy[i], 2);
    model.store_velocities(sys);
    EXPECT_NEAR(mean_square_velocity(sys.particles), sum / 4.0 / static_cast<double>(p.n), 1e-15);
}
