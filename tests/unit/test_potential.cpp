#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "jamsim/core/system.hpp"
#include "jamsim/force/force_field.hpp"
#include "jamsim/force/pair_forces.hpp"
#include "jamsim/potential/soft_sphere.hpp"

using namespace jamsim;

namespace {
double energy_of(const potential::SoftSphere& pot, double r, double d) {
    return std::visit([&](const auto& e) { return e(r * r, d).energy; }, pot);
}
double force_of(const potential::SoftSphere& pot, double r, double d) {
    return std::visit([&](const auto& e) { return e(r * r, d).force_over_r * r; }, pot);
}
}  // namespace

// F = −dV/dr by central differences, for the dedicated kernels and the generic one.
TEST(Potential, ForceIsMinusEnergyDerivative) {
    for (double alpha : {2.0, 2.5, 3.0, 1.5}) {
        const auto pot = potential::make_soft_sphere(alpha, 1.3);
        for (double d : {1.0, 1.2, 1.4})
            for (double r : {0.3, 0.7, 0.95, 0.999 * d}) {
                const double h = 1e-6;
                const double fd = -(energy_of(pot, r + h, d) - energy_of(pot, r - h, d)) / (2 * h);
                EXPECT_NEAR(force_of(pot, r, d), fd, 1e-8) << "alpha " << alpha;
            }
    }
}

TEST(Potential, AnalyticValuesAndFastKernelsMatchGeneric) {
    const double ke = 1.7, d = 1.2, r = 0.9;
    const double overlap = 1 - r / d;
    for (double alpha : {2.0, 2.5}) {
        const auto fast = potential::make_soft_sphere(alpha, ke);
        const potential::SoftSphere generic = potential::PowerLaw{ke, alpha};
        const double v = ke / alpha * std::pow(overlap, alpha);
        const double f = ke / d * std::pow(overlap, alpha - 1);
        EXPECT_NEAR(energy_of(fast, r, d), v, 1e-15);
        EXPECT_NEAR(force_of(fast, r, d), f, 1e-15);
        EXPECT_NEAR(energy_of(generic, r, d), v, 1e-15);
        EXPECT_NEAR(force_of(generic, r, d), f, 1e-15);
    }
    EXPECT_TRUE(std::holds_alternative<potential::Harmonic>(potential::make_soft_sphere(2.0)));
    EXPECT_TRUE(std::holds_alternative<potential::Hertzian>(potential::make_soft_sphere(2.5)));
    EXPECT_THROW(potential::make_soft_sphere(1.0), std::invalid_argument);
}

// Two disks (d = 1 and 1.4, so d_ij = 1.2) overlapping across the sheared y boundary:
// energy, forces, pressure and shear stress against hand-written formulas.
TEST(Potential, TwoParticleAnalyticAcrossShearedBoundary) {
    const double L = 6.0, gamma = 0.3;
    Particles p;
    p.resize(2);
    p.diameter = {1.0, 1.4};
    p.tag = {0, 1};
    // Lab separation wanted: r = (0.6, 0.8), |r| = 1.0 < 1.2. Put j near the top edge and i
    // near the bottom so the contact goes through the Lees–Edwards boundary:
    // i at sheared (2.0, 0.3); j's image below at y_j − L = 0.3 − 0.8 = −0.5.
    const double rx = 0.6, ry = 0.8;
    p.x[0] = 2.0;
    p.y[0] = 0.3;
    p.y[1] = p.y[0] - ry + L;
    // lab: x_i + γ y_i − (x_j + γ (y_j − L)) = rx  ⇒  x_j = x_i + γ (y_i − y_j + L) − rx
    p.x[1] = p.x[0] + gamma * (p.y[0] - p.y[1] + L) - rx;
    System sys{p, Box(L)};
    sys.box.set_strain_unwrapped(gamma);
    for (double alpha : {2.0, 2.5}) {
        ForceField ff(potential::make_soft_sphere(alpha), 0.3);
        const ForceResult f = ff.compute(sys);
        const double r = 1.0, d = 1.2, overlap = 1 - r / d;
        const double fmag = std::pow(overlap, alpha - 1) / d;
        EXPECT_NEAR(f.energy, std::pow(overlap, alpha) / alpha, 1e-14);
        EXPECT_EQ(f.contacts, 1);
        // force on the disk at the bottom (tag 0) points along r = r_0 − r_1
        const auto& q = sys.particles;
        const std::size_t i0 = q.tag[0] == 0 ? 0 : 1, i1 = 1 - i0;
        EXPECT_NEAR(q.fx[i0], fmag * rx / r, 1e-14);
        EXPECT_NEAR(q.fy[i0], fmag * ry / r, 1e-14);
        EXPECT_NEAR(q.fx[i1], -fmag * rx / r, 1e-14);
        EXPECT_NEAR(q.fy[i1], -fmag * ry / r, 1e-14);
        // p = r·f / (2A), σ = −r_x f_y / A
        EXPECT_NEAR(f.pressure(sys.box), fmag * r / (2 * L * L), 1e-15);
        EXPECT_NEAR(f.shear_stress(sys.box), -rx * fmag * ry / r / (L * L), 1e-15);
    }
}

// The blocked evaluator (vectorised, possibly an AVX2 clone picked at load time) gives the
// very same bits as the scalar evaluator: only IEEE-exact lane-wise operations are used.
TEST(Potential, BlockEvaluatorBitwiseEqualsScalar) {
    const std::size_t m = 1003;  // odd: exercises the vector remainder
    std::vector<double> r2(m), d(m), fr(m), en(m), fr_only(m);
    for (std::size_t k = 0; k < m; ++k) {
        d[k] = (k % 3 == 0) ? 1.0 : (k % 3 == 1 ? 1.2 : 1.4);
        const double r = d[k] * (0.5 + 0.7 * static_cast<double>(k) / m);  // contacts and not
        r2[k] = r * r;
    }
    const potential::Harmonic harmonic{1.0};
    const potential::Hertzian hertzian{1.0};
    evaluate_block(harmonic, r2.data(), d.data(), fr.data(), en.data(), m);
    evaluate_block(harmonic, r2.data(), d.data(), fr_only.data(), nullptr, m);
    for (std::size_t k = 0; k < m; ++k) {
        const auto t = harmonic(r2[k], d[k]);
        ASSERT_EQ(fr[k], t.force_over_r) << k;
        ASSERT_EQ(en[k], t.energy) << k;
        ASSERT_EQ(fr_only[k], t.force_over_r) << k;
    }
    evaluate_block(hertzian, r2.data(), d.data(), fr.data(), en.data(), m);
    for (std::size_t k = 0; k < m; ++k) {
        const auto t = hertzian(r2[k], d[k]);
        ASSERT_EQ(fr[k], t.force_over_r) << k;
        ASSERT_EQ(en[k], t.energy) << k;
    }
}
