// The sheared ensemble (Paper I): quasistatic shear mixes a configuration until its jamming
// density φ_J no longer remembers how it was prepared, while compression alone keeps the
// memory of the preparation (cooling before compression raises φ_J).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "jamsim/dynamics/replica.hpp"
#include "jamsim/protocols/jamming.hpp"
#include "jamsim/protocols/preparation.hpp"
#include "support/statistics.hpp"

using namespace jamsim;

namespace {

constexpr std::int64_t kDisks = 64;
constexpr int kSeeds = 24;

/// φ_J of one configuration: random start at φ = 0.86, optionally cooled (T₀ = 1e-3 over
/// t = 2e4, RD0 with noise) and optionally sheared quasistatically to `strain` (Δγ = 1e-3),
/// then compressed/decompressed to its own φ_J.
double jamming_density(std::uint64_t seed, bool cooled, double strain) {
    ReplicaParams p;
    p.model = "RAND";
    p.n = kDisks;
    p.phi = 0.86;
    p.seed = seed;
    System sys = initial_system(p);
    ForceField forces(potential::make_soft_sphere(p.alpha), p.skin);
    auto cg = make_minimizer("cg");
    const MinimizeCriteria c;
    if (cooled) cool(sys, forces, {1e-3, 2e4, p.dt, p.kd}, RngStream(seed, 0, RngPurpose::ThermalNoise));
    if (strain > 0.0) shear_quasistatically(sys, forces, *cg, c, strain, 1e-3);
    return find_jamming_point(sys, forces, *cg, c).phi_j;
}

jamsim::testing::Estimate ensemble(bool cooled, double strain, std::vector<double>* values = nullptr) {
    std::vector<double> phi_j;
    for (int s = 1; s <= kSeeds; ++s) phi_j.push_back(jamming_density(static_cast<std::uint64_t>(s), cooled, strain));
    if (values) *values = phi_j;
    return jamsim::testing::mean_and_error(phi_j);
}

} // namespace

// Compression keeps the preparation: cooled configurations jam at a higher φ_J than random
// ones (3σ apart). After QS shear to γ = 2 the two preparations give the same ⟨φ_J⟩ (within
// 3 combined standard errors), and the gap between them has shrunk by more than 3 combined
// standard errors. The first check gives the others their power: a test that cannot tell the
// preparations apart before shear could not show that shear erases the difference.
TEST(ShearedEnsemble, ForgetsThePreparation) {
    std::vector<double> v[4];
    const auto rand = ensemble(false, 0.0, &v[0]), cooled = ensemble(true, 0.0, &v[1]);
    const auto rand_sheared = ensemble(false, 2.0, &v[2]), cooled_sheared = ensemble(true, 2.0, &v[3]);
    auto spread = [](const std::vector<double>& x, const jamsim::testing::Estimate& e) {
        return e.error * std::sqrt(static_cast<double>(x.size()));
    };
    std::printf("<phi_J> over %d seeds, N = %lld (standard deviation): RAND %.5f +- %.5f (%.4f), "
                "cooled %.5f +- %.5f (%.4f); after QS shear to 2: RAND %.5f +- %.5f (%.4f), "
                "cooled %.5f +- %.5f (%.4f)\n",
                kSeeds, static_cast<long long>(kDisks), rand.mean, rand.error, spread(v[0], rand),
                cooled.mean, cooled.error, spread(v[1], cooled), rand_sheared.mean,
                rand_sheared.error, spread(v[2], rand_sheared), cooled_sheared.mean,
                cooled_sheared.error, spread(v[3], cooled_sheared));
    const double gap_before = cooled.mean - rand.mean, gap_after = cooled_sheared.mean - rand_sheared.mean;
    const double error_before = std::hypot(cooled.error, rand.error);
    const double error_after = std::hypot(cooled_sheared.error, rand_sheared.error);
    EXPECT_GT(gap_before, 3.0 * error_before);
    EXPECT_LE(std::abs(gap_after), 3.0 * error_after);
    EXPECT_GT(gap_before - std::abs(gap_after), 3.0 * std::hypot(error_before, error_after));
}
