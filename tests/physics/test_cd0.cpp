#include <gtest/gtest.h>

#include <cmath>

#include "jamsim/dynamics/cd0.hpp"
#include "jamsim/force/force_field.hpp"
#include "jamsim/run/replica.hpp"

using namespace jamsim;

// Without shear CD0 dissipates: dE/dt = −Σ f_i·u_i = −k_d uᵀA u ≤ 0 (A is positive definite),
// so with a stable time step the energy never increases.
TEST(Cd0, EnergyDecreasesWithoutShear) {
    ReplicaParams p;
    p.model = "CD0";
    p.n = 128;
    p.phi = 0.84;
    p.rate = 0.0;
    p.time = 100.0;
    p.sample_interval = 1.0;
    p.seed = 3;
    const auto r = run_replica(p);
    for (std::size_t k = 1; k < r.series.size(); ++k)
        ASSERT_LE(r.series[k].energy_per_particle, r.series[k - 1].energy_per_particle) << k;
    // The start is relaxed already (relax_cd0_start); the energy still falls clearly.
    EXPECT_LT(r.series[r.series.size() - 1].energy_per_particle, 0.5 * r.series[0].energy_per_particle);
}

// A CD0 replica from random positions starts from them relaxed (relax_cd0_start): its first
// sample's energy is far below that of the random positions themselves, and above zero (φ =
// 0.84 is above jamming, so the relaxation leaves overlaps: it is not a minimisation).
TEST(Cd0, RandomStartIsRelaxedBeforeTheFirstSolve) {
    ReplicaParams p;
    p.model = "CD0";
    p.n = 1024;
    p.phi = 0.84;
    p.rate = 1e-3;
    p.strain = 0.002;
    p.sample_interval = 0.002;
    const auto r = run_replica(p);
    System random = initial_system(p);
    ForceField ff(potential::make_soft_sphere(p.alpha), p.skin);
    const double random_energy = ff.compute(random, Tally::Full).energy / static_cast<double>(p.n);
    EXPECT_LT(r.series[0].energy_per_particle, 0.05 * random_energy);  // about 1/50 measured
    EXPECT_GT(r.series[0].energy_per_particle, 0.0);
    // start_system is that start, and initial_system the random positions (other models).
    EXPECT_NE(start_system(p).particles.x, initial_system(p).particles.x);
    p.model = "RD0";
    EXPECT_EQ(start_system(p).particles.x, initial_system(p).particles.x);
}

// Two overlapping disks alone: A = [[1+δ, −1], [−1, 1+δ]], so u_1 = −u_2 = f_1/(k_d (2+δ)).
TEST(Cd0, TwoDisksAnalytic) {
    Particles q;
    q.resize(2);
    q.diameter = {1.0, 1.0};
    q.tag = {0, 1};
    q.x = {2.0, 2.6};
    q.y = {2.0, 2.3};
    System sys{q, Box(6.0)};
    ForceField ff(potential::make_soft_sphere(2.0), 0.3);
    ff.compute(sys);
    const double kd = 2.0, delta = 0.05;
    Cd0 model(ReplicaParams{.integrator = "euler", .kd = kd, .delta = delta});
    model.prepare(sys, ff, 0.0);
    const auto& s = sys.particles;
    for (std::size_t i = 0; i < 2; ++i) {
        EXPECT_NEAR(s.ux[i], s.fx[i] / (kd * (2 + delta)), 1e-12);
        EXPECT_NEAR(s.uy[i], s.fy[i] / (kd * (2 + delta)), 1e-12);
    }
    EXPECT_GT(std::abs(s.ux[0]), 1e-3);
}
