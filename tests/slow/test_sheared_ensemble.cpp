// The sheared ensemble (Paper I): quasistatic shear mixes a configuration until its jamming
// density φ_J no longer remembers how it was prepared, while compression alone keeps the
// memory of the preparation (cooling before compression raises φ_J).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "jamsim/run/replica.hpp"
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

}  // namespace

// Compression keeps the preparation: cooled configurations jam at a higher φ_J than random
// ones. After QS shear to γ = 2 the gap between the preparations has shrunk, and what is left
// of it is consistent with zero. The four ensembles share their seeds (a cooled start is the
// random start of the same seed, cooled), so the comparisons use per-seed differences and
// their standard errors: gap_s = φ_J(cooled, s) − φ_J(random, s) before and after shear.
//   - before: ⟨gap⟩ > 3 standard errors (the preparations differ; this gives the test power);
//   - shrink: ⟨gap_before − gap_after⟩ > 3 standard errors (shear erases most of it);
//   - after: |⟨gap⟩| ≤ 3 standard errors (consistent with no memory left).
TEST(ShearedEnsemble, ForgetsThePreparation) {
    std::vector<double> v[4];
    ensemble(false, 0.0, &v[0]);
    ensemble(true, 0.0, &v[1]);
    ensemble(false, 2.0, &v[2]);
    ensemble(true, 2.0, &v[3]);
    std::vector<double> before, after, shrink;
    for (int s = 0; s < kSeeds; ++s) {
        before.push_back(v[1][s] - v[0][s]);
        after.push_back(v[3][s] - v[2][s]);
        shrink.push_back(before.back() - after.back());
    }
    using jamsim::testing::mean_and_error;
    const auto b = mean_and_error(before), a = mean_and_error(after), d = mean_and_error(shrink);
    std::printf("<phi_J> over %d seeds, N = %lld: RAND %.5f, cooled %.5f; after QS shear to 2: "
                "RAND %.5f, cooled %.5f\n",
                kSeeds, static_cast<long long>(kDisks), mean_and_error(v[0]).mean, mean_and_error(v[1]).mean,
                mean_and_error(v[2]).mean, mean_and_error(v[3]).mean);
    std::printf("paired gaps cooled - random: before %.5f +- %.5f, after %.5f +- %.5f, shrink "
                "%.5f +- %.5f\n",
                b.mean, b.error, a.mean, a.error, d.mean, d.error);
    EXPECT_GT(b.mean, 3.0 * b.error);
    EXPECT_GT(d.mean, 3.0 * d.error);
    EXPECT_LE(std::abs(a.mean), 3.0 * a.error);
}
