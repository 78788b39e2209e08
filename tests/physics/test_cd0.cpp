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
    EXPECT_LT(r.series[r.series.size() - 1].energy_per_particle,
              0.1 * r.series[0].energy_per_particle);
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
