// Step-by-step energy balance. Along the exact dynamics of every model,
//   dH/dt = P_in − P_dis,  H = E + K,  P_in = (σ + σ_dis + σ_kin) γ̇ A,
// so over one step from a state S the residual
//   R(h) = H(S_h) − H(S) − (h/2) [Q(S) + Q(S_h)],  Q = P_in − P_dis,
// is the integrator's local error plus the trapezoid rule's (O(h³)). A scheme of order p
// has a local error O(h^{p+1}): R(h)/R(h/2) → 2^{p+1}, i.e. 8 for Heun and for RD's Strang
// splitting, 4 for forward Euler. The ratio is checked on two successive halvings, h0/h0/2
// and h0/2 : h0/4, from the same sheared state with no contact forming or breaking during
// the step (contacts change the smoothness class of the harmonic potential); the limit 2^{p+1}
// is approached with a relative deviation O(h), so the second ratio must lie closer to it
// and within 15% (h0 is chosen so that the next order contributes only a few per cent).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "jamsim/force/force_field.hpp"
#include "jamsim/dynamics/model.hpp"
#include "jamsim/run/replica.hpp"

using namespace jamsim;

namespace {

struct Balance {
    double h = 0;  // E + K
    double q = 0;  // P_in − P_dis
    std::int64_t contacts = 0;
};

Balance balance(System& sys, ForceField& ff, Model& model, double rate) {
    const ForceResult f = ff.compute(sys, Tally::Full);
    model.prepare(sys, ff, rate);
    model.store_velocities(sys);
    const Dissipation d = model.dissipation(sys, ff, rate);
    const double sigma = f.shear_stress(sys.box) + d.shear_stress + d.shear_stress_kinetic;
    return {f.energy + d.kinetic_energy, sigma * rate * sys.box.area() - d.power, f.contacts};
}

/// R(h) from state `start`, with a fresh model (no solver state carried over).
double residual(const System& start, const ReplicaParams& p, double h, bool* contacts_changed) {
    System sys = start;
    ForceField ff(potential::make_soft_sphere(p.alpha), p.skin);
    auto model = model_of(p).make(p, random_key(p));
    const Balance b0 = balance(sys, ff, *model, p.rate);
    model->advance(sys, ff, h, p.rate, 0);
    const Balance b1 = balance(sys, ff, *model, p.rate);
    *contacts_changed = b0.contacts != b1.contacts;
    return b1.h - b0.h - 0.5 * h * (b0.q + b1.q);
}

void check_order(const std::string& name, const std::string& integ, double expected_ratio) {
    ReplicaParams p;
    p.model = name;
    p.integrator = integ;
    p.n = 64;
    p.phi = 0.85;
    p.rate = 1e-2;
    p.mass = 1.0;
    p.seed = 11;
    // A sheared state: run the model for a while, with its own velocities.
    System sys = initial_system(p);
    {
        ForceField ff(potential::make_soft_sphere(p.alpha), p.skin);
        auto model = model_of(p).make(p, random_key(p));
        for (int s = 0; s < 1000; ++s) {
            ff.compute(sys, Tally::ForcesOnly);
            model->prepare(sys, ff, p.rate);
            model->advance(sys, ff, 0.05, p.rate, 0);
        }
    }
    // Four step sizes; the order is read from the two smallest pairs, where the next term of
    // the local error (relative size ∝ h) matters least.
    const double h0 = 0.02;
    bool changed[4];
    const double r0 = residual(sys, p, h0, &changed[0]);
    const double r1 = residual(sys, p, h0 / 2, &changed[1]);
    const double r2 = residual(sys, p, h0 / 4, &changed[2]);
    const double r3 = residual(sys, p, h0 / 8, &changed[3]);
    ASSERT_FALSE(changed[0] || changed[1] || changed[2] || changed[3]) << name << ": pick another state";
    const double q1 = r1 / r2, q2 = r2 / r3;
    std::printf("%s: R(h) = %.3e %.3e %.3e %.3e, ratios %.3f %.3f %.3f (expected %.0f)\n", name.c_str(), r0, r1, r2, r3,
                r0 / r1, q1, q2, expected_ratio);
    EXPECT_LE(std::abs(q2 / expected_ratio - 1.0), 0.15) << name;
    EXPECT_LE(std::abs(q2 / expected_ratio - 1.0), std::abs(q1 / expected_ratio - 1.0) + 0.02) << name;
}

}  // namespace

TEST(StepEnergyBalance, Rd0Heun) { check_order("RD0", "heun", 8.0); }
TEST(StepEnergyBalance, Rd0Euler) { check_order("RD0", "euler", 4.0); }
TEST(StepEnergyBalance, Cd0Heun) { check_order("CD0", "heun", 8.0); }
TEST(StepEnergyBalance, RdSplitting) { check_order("RD", "heun", 8.0); }
TEST(StepEnergyBalance, CdHeun) { check_order("CD", "heun", 8.0); }
TEST(StepEnergyBalance, CdnHeun) { check_order("CDn", "heun", 8.0); }
TEST(StepEnergyBalance, CdtHeun) { check_order("CDt", "heun", 8.0); }
