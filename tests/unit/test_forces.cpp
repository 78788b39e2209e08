#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "jamsim/force/force_field.hpp"
#include "support/configurations.hpp"

using namespace jamsim;
using jamsim::testing::brute_force;
using jamsim::testing::random_configuration;

namespace {

ForceResult forces_of(System& sys, double alpha) {
    ForceField ff(potential::make_soft_sphere(alpha), 0.3);
    return ff.compute(sys);
}

double energy_of(System sys, double alpha) { return forces_of(sys, alpha).energy; }

/// Force on the particle with tag t after compute() (which may reorder particles).
std::size_t index_of_tag(const Particles& p, std::int32_t t) {
    return static_cast<std::size_t>(std::find(p.tag.begin(), p.tag.end(), t) - p.tag.begin());
}

struct Case {
    std::int64_t n;
    double phi;
};

}  // namespace

// Forces, energy, p and σ from the neighbour list against a brute-force sum over explicit
// images, with particles straddling every edge and corner, at several strains. N = 40 takes
// the all-pairs list path, N = 400 the cell-list path.
TEST(PairForces, NeighbourListEqualsBruteForceImages) {
    for (const Case c : {Case{40, 0.88}, Case{400, 0.88}, Case{400, 0.75}})
        for (double gamma : {-0.49, -0.2, 0.0, 0.3, 0.49})
            for (double alpha : {2.0, 2.5}) {
                System sys = random_configuration(c.n, c.phi, gamma, 11);
                const auto pot = potential::make_soft_sphere(alpha);
                const auto ref = brute_force(sys, pot);
                const ForceResult f = forces_of(sys, alpha);
                ASSERT_GT(ref.contacts, c.n / 2);
                EXPECT_EQ(f.contacts, ref.contacts) << "N " << c.n << " gamma " << gamma;
                const double tol = 1e-12 * std::max(1.0, std::abs(ref.energy));
                EXPECT_NEAR(f.energy, ref.energy, tol);
                EXPECT_NEAR(f.virial_xx, ref.vxx, 1e-11);
                EXPECT_NEAR(f.virial_xy, ref.vxy, 1e-11);
                EXPECT_NEAR(f.virial_yy, ref.vyy, 1e-11);
                const Particles& p = sys.particles;
                for (std::size_t k = 0; k < p.size(); ++k) {
                    const auto t = static_cast<std::size_t>(p.tag[k]);
                    ASSERT_NEAR(p.fx[k], ref.fx[t], 1e-12) << "tag " << t << " gamma " << gamma;
                    ASSERT_NEAR(p.fy[k], ref.fy[t], 1e-12) << "tag " << t << " gamma " << gamma;
                }
            }
}

// F_i = −∂E/∂r_i (lab frame) by central differences. Moving particle i by h in lab x is
// sheared x += h; moving it by h in lab y at fixed lab x is y += h, x −= γ h.
TEST(PairForces, ForcesAreMinusEnergyGradient) {
    for (const Case c : {Case{40, 0.9}, Case{300, 0.9}})
        for (double alpha : {2.0, 2.5})
            for (double gamma : {-0.4, 0.0, 0.35}) {
                System base = random_configuration(c.n, c.phi, gamma, 3);
                System evaluated = base;
                forces_of(evaluated, alpha);
                const double h = 1e-6;
                for (std::int32_t t = 0; t < 12; ++t) {
                    const auto i = static_cast<std::size_t>(t);
                    System xp = base, xm = base, yp = base, ym = base;
                    xp.particles.x[i] += h;
                    xm.particles.x[i] -= h;
                    yp.particles.y[i] += h;
                    yp.particles.x[i] -= gamma * h;
                    ym.particles.y[i] -= h;
                    ym.particles.x[i] += gamma * h;
                    const double fx_fd = -(energy_of(xp, alpha) - energy_of(xm, alpha)) / (2 * h);
                    const double fy_fd = -(energy_of(yp, alpha) - energy_of(ym, alpha)) / (2 * h);
                    const auto k = index_of_tag(evaluated.particles, t);
                    // Central-difference error O(h² V''') ~ 1e-12 plus round-off ε E / h ~ 1e-9.
                    EXPECT_NEAR(evaluated.particles.fx[k], fx_fd, 2e-8);
                    EXPECT_NEAR(evaluated.particles.fy[k], fy_fd, 2e-8);
                }
            }
}

// p = −dE/dA under an affine compression, σ = (1/A) dE/dγ under an affine shear.
TEST(PairForces, PressureAndShearStressAreStrainDerivatives) {
    for (double alpha : {2.0, 2.5})
        for (double gamma : {-0.3, 0.0, 0.2}) {
            System base = random_configuration(300, 0.88, gamma, 5);
            System evaluated = base;
            const ForceResult f = forces_of(evaluated, alpha);
            const double h = 1e-6;
            auto scaled = [&](double s) {
                System out = base;
                out.box = Box(base.box.side() * s);
                out.box.set_strain_unwrapped(gamma);
                for (auto& v : out.particles.x) v *= s;
                for (auto& v : out.particles.y) v *= s;
                return energy_of(out, alpha);
            };
            // A(s) = s² L², dA/ds = 2 L² at s = 1
            const double dE_ds = (scaled(1 + h) - scaled(1 - h)) / (2 * h);
            const double p_fd = -dE_ds / (2 * base.box.area());
            EXPECT_NEAR(f.pressure(evaluated.box), p_fd, 1e-9 + 1e-6 * std::abs(p_fd));
            auto sheared = [&](double g) {
                System out = base;
                out.box.set_strain_unwrapped(g);
                return energy_of(out, alpha);
            };
            const double sigma_fd = (sheared(gamma + h) - sheared(gamma - h)) / (2 * h) / base.box.area();
            EXPECT_NEAR(f.shear_stress(evaluated.box), sigma_fd, 1e-9 + 1e-6 * std::abs(sigma_fd));
        }
}

// A configuration at γ just below 1/2 and its twin after the Lees–Edwards wrap (γ − 1,
// x → x + y) are the same physical state: same distances, energy and stress.
TEST(PairForces, WrappedTwinIsIdentical) {
    const double gamma = 0.5 - 1e-9;
    System a = random_configuration(300, 0.86, gamma, 9);
    System b = a;
    b.box.set_strain_unwrapped(gamma - 1.0);
    b.box.remap_after_wrap(1, b.particles.x, b.particles.y);
    for (auto i = 0u; i < b.particles.size(); ++i) b.box.wrap_into_cell(b.particles.x[i], b.particles.y[i]);
    // every pair's minimum-image distance
    for (std::size_t i = 0; i < 60; ++i)
        for (std::size_t j = i + 1; j < a.particles.size(); ++j) {
            const auto ra = a.box.min_image(a.particles.x[i] - a.particles.x[j], a.particles.y[i] - a.particles.y[j]);
            const auto rb = b.box.min_image(b.particles.x[i] - b.particles.x[j], b.particles.y[i] - b.particles.y[j]);
            ASSERT_NEAR(std::sqrt(norm2(ra)), std::sqrt(norm2(rb)), 1e-12);
        }
    const auto fa = forces_of(a, 2.0), fb = forces_of(b, 2.0);
    EXPECT_EQ(fa.contacts, fb.contacts);
    EXPECT_NEAR(fa.energy, fb.energy, 1e-12);
    EXPECT_NEAR(fa.pressure(a.box), fb.pressure(b.box), 1e-13);
    EXPECT_NEAR(fa.shear_stress(a.box), fb.shear_stress(b.box), 1e-13);
}

// The force loop's contact record (ContactRecord, which CD0 reads instead of walking the
// pairs again) against a walk of the same list with for_each_pair: the same flags and the
// same sums, bitwise, at strains with pairs across the sheared boundary; the forces are those
// of an evaluation that records nothing; and a record is offered only for the positions and
// strain it was made at.
TEST(PairForces, ContactRecordEqualsPairWalk) {
    for (double gamma : {-0.45, 0.0, 0.3})
        for (Tally tally : {Tally::Full, Tally::ForcesOnly}) {
            System sys = random_configuration(400, 0.86, gamma, 23);
            System plain = sys;
            ForceField ff(potential::make_soft_sphere(2.0), 0.3);
            ff.compute(sys, tally);
            EXPECT_FALSE(ff.recorded_contacts(sys.box, sys.particles.x, sys.particles.y))
                << "a record before recording was asked for";
            ff.record_contacts();
            ff.compute(sys, tally);
            const Particles& p = sys.particles;
            const auto record = ff.recorded_contacts(sys.box, p.x, p.y);
            ASSERT_TRUE(record);
            ASSERT_EQ(record->touching.size(), ff.list().size());
            ASSERT_EQ(record->sum_ry.size(), p.size());
            std::vector<std::uint8_t> touching(ff.list().size());
            std::vector<double> sum_ry(p.size(), 0.0);
            std::size_t contacts = 0, crossing = 0;
            for_each_pair(ff.list(), sys.box, p.x, p.y,
                          [&](std::size_t k, std::size_t i, std::size_t j, Vec2 r, bool touches) {
                              touching[k] = touches;
                              sum_ry[i] += r.y * static_cast<double>(touches);
                              sum_ry[j] -= r.y * static_cast<double>(touches);
                              contacts += touches;
                              crossing += touches && ff.list().shift_y()[k] != 0.0;
                          });
            ASSERT_GT(contacts, p.size());
            ASSERT_GT(crossing, 0u) << "no contact across the sheared boundary";
            for (std::size_t k = 0; k < touching.size(); ++k) ASSERT_EQ(record->touching[k], touching[k]) << k;
            for (std::size_t i = 0; i < p.size(); ++i)
                ASSERT_EQ(std::memcmp(&record->sum_ry[i], &sum_ry[i], sizeof(double)), 0)
                    << "disk " << i << ": " << record->sum_ry[i] << " against " << sum_ry[i];
            // Recording leaves the forces' bits alone.
            ForceField quiet(potential::make_soft_sphere(2.0), 0.3);
            quiet.compute(plain, tally);
            ASSERT_EQ(plain.particles.tag, p.tag);
            EXPECT_EQ(plain.particles.fx, p.fx);
            EXPECT_EQ(plain.particles.fy, p.fy);
            // Other positions, another strain, or a minimiser's evaluation: no record.
            std::vector<double> x_copy(p.x.begin(), p.x.end());
            EXPECT_FALSE(ff.recorded_contacts(sys.box, x_copy, p.y));
            Box sheared = sys.box;
            sheared.set_strain_unwrapped(gamma + 1e-6);
            EXPECT_FALSE(ff.recorded_contacts(sheared, p.x, p.y));
            std::vector<double> zero(p.size(), 0.0), fx(p.size()), fy(p.size());
            ff.compute_split(sys.box, p.x, p.y, p.x, p.y, zero, zero, p.diameter, fx, fy, tally);
            EXPECT_FALSE(ff.recorded_contacts(sys.box, p.x, p.y));
        }
}
