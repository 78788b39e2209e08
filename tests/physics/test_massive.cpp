// The massive models RD, CD, CDn, CDt under SLLOD (thesis §4.6).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "jamsim/force/force_field.hpp"
#include "jamsim/run/replica.hpp"
#include "jamsim/dynamics/sllod.hpp"
#include "support/statistics.hpp"

using namespace jamsim;

namespace {

using Stat = jamsim::testing::Estimate;
Stat over(const std::vector<double>& v) { return jamsim::testing::mean_and_error(v); }

ReplicaParams massive(const std::string& model, std::uint64_t seed) {
    ReplicaParams p;
    p.model = model;
    p.mass = 1.0;
    p.dt = 0.05;
    p.n = 128;
    p.phi = 0.80;
    p.rate = 3e-3;
    p.transient = 0.5;
    p.strain = 2.0;
    p.seed = seed;
    return p;
}

/// Total momentum Σ m_i u_i.
Vec2 momentum(const System& sys, double mass) {
    Vec2 m;
    for (std::size_t i = 0; i < sys.particles.size(); ++i) {
        const double mi = mass * sys.particles.diameter[i] * sys.particles.diameter[i];
        m.x += mi * sys.particles.ux[i];
        m.y += mi * sys.particles.uy[i];
    }
    return m;
}

}  // namespace

// Steady state: shear work (σ + σ_dis + σ_kin) γ̇ A equals the dissipated power plus
// d(E + K)/dt, which averages to zero; per-seed differences must be consistent with zero.
TEST(Massive, EnergyBalance) {
    for (const char* model : {"RD", "CD", "CDn", "CDt"}) {
        std::vector<double> diff, input;
        for (std::uint64_t seed = 1; seed <= 4; ++seed) {
            const ReplicaParams p = massive(model, seed);
            const auto r = run_replica(p);
            const double in = mean_after(r.series, &Sample::input_power, p.transient);
            input.push_back(in);
            diff.push_back(in - mean_after(r.series, &Sample::dissipated_power, p.transient));
        }
        const Stat d = over(diff), in = over(input);
        std::printf("%s: P_in = %.4g, <P_in - P_dis> = %.3g +- %.2g\n", model, in.mean, d.mean, d.error);
        EXPECT_LT(std::abs(d.mean), 3 * d.error + 1e-15) << model;
        EXPECT_LT(std::abs(d.mean), 0.03 * in.mean) << model;
    }
}

// Pairwise dissipation conserves the total non-affine momentum (started from a uniform
// offset in u_x, so Σ m u_y = 0 keeps the SLLOD term −γ̇ Σ m u_y from acting); the
// reservoir drag of RD makes it relax towards zero.
TEST(Massive, Momentum) {
    for (const char* model : {"RD", "CD", "CDn", "CDt"}) {
        ReplicaParams p = massive(model, 2);
        System sys = initial_system(p);
        ForceField ff(potential::make_soft_sphere(2.0), p.skin);
        auto m = model_of(p).make(p, random_key(p));
        for (auto& u : sys.particles.ux) u = 0.1;
        const Vec2 start = momentum(sys, p.mass);
        for (int s = 0; s < 2000; ++s) {  // t = 100 ≫ m/k_d
            ff.compute(sys, Tally::ForcesOnly);
            m->prepare(sys, ff, p.rate);
            m->advance(sys, ff, p.dt, p.rate, 0);
        }
        const Vec2 end = momentum(sys, p.mass);
        if (std::string(model) == "RD") {
            EXPECT_LT(std::abs(end.x), 1e-3 * start.x) << model;
        } else {
            EXPECT_NEAR(end.x, start.x, 1e-10 * start.x) << model;
            EXPECT_NEAR(end.y, 0.0, 1e-10 * start.x) << model;
        }
    }
}

// A dilute gas (no contacts) keeps the affine profile: u stays zero and the sheared
// coordinates do not move, while γ advances.
TEST(Massive, DiluteGasStaysAffine) {
    for (const char* model : {"RD", "CD", "CDn", "CDt"}) {
        ReplicaParams p = massive(model, 3);
        p.n = 16;
        p.phi = 0.002;  // about 0.06 overlapping pairs expected at random placement
        System sys = initial_system(p);
        ForceField ff(potential::make_soft_sphere(2.0), p.skin);
        ff.compute(sys);
        const auto x0 = sys.particles.x, y0 = sys.particles.y;
        ASSERT_EQ(ff.compute(sys).contacts, 0) << "dilute start must have no contacts";
        auto m = model_of(p).make(p, random_key(p));
        for (int s = 0; s < 500; ++s) {
            ff.compute(sys, Tally::ForcesOnly);
            m->prepare(sys, ff, p.rate);
            m->advance(sys, ff, p.dt, p.rate, 0);
        }
        for (std::size_t i = 0; i < sys.particles.size(); ++i) {
            ASSERT_EQ(sys.particles.ux[i], 0.0);
            ASSERT_EQ(sys.particles.uy[i], 0.0);
        }
        EXPECT_EQ(sys.particles.x, x0);
        EXPECT_EQ(sys.particles.y, y0);
        EXPECT_NEAR(sys.box.strain(), 500 * p.dt * p.rate, 1e-15);
    }
}

// RD with a small mass reproduces RD0 (the overdamped limit): ⟨p⟩ at φ = 0.80, γ̇ = 1e-3
// agrees within 3 combined standard errors over seeds.
TEST(Massive, SmallMassRdReproducesRd0) {
    std::vector<double> rd, rd0;
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
        ReplicaParams p;
        p.n = 128;
        p.phi = 0.80;
        p.rate = 1e-3;
        p.transient = 0.5;
        p.strain = 2.0;
        p.seed = seed;
        p.integrator = "heun";
        p.dt = 0.05;
        rd0.push_back(mean_after(run_replica(p).series, &Sample::pressure, p.transient));
        p.model = "RD";
        p.mass = 0.01;
        p.dt = 0.01;
        rd.push_back(mean_after(run_replica(p).series, &Sample::pressure, p.transient));
    }
    const Stat a = over(rd0), b = over(rd);
    std::printf("<p>: RD0 %.4g +- %.2g, RD (m = 0.01) %.4g +- %.2g\n", a.mean, a.error, b.mean, b.error);
    EXPECT_LT(std::abs(a.mean - b.mean), 3 * std::hypot(a.error, b.error));
    EXPECT_LT(a.error, 0.1 * a.mean);
}
