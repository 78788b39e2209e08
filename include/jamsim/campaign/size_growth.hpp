#pragma once
// A minimisation's throughput at a size that was not measured, from the sizes that were
// (costs.cpp): its seconds per cost unit grow with N (the iterations do, which its cost
// estimate does not count), and a few seeds per size measure that growth only roughly (one
// replica's cost varies several-fold between seeds near phi_J), so the growth fitted to the
// sizes measured is weighed against the growth minimisations showed here before, each by its
// uncertainty, and every size measured contributes to the level, the nearest and best
// measured the most.
#include <span>

namespace jamsim {

/// A throughput measured at one size: seconds per estimated cost unit, over `replicas`
/// replicas (seeds).
struct SizeRate {
    double n = 0;
    double seconds_per_cost = 0;
    double replicas = 1;
};

/// The growth expected before measuring: d ln(seconds per cost unit) / d ln N = slope ±
/// sigma. Minimisations (RAND, QS, COMPRESS; slurm/README, "Minimisations at larger N")
/// showed 0.41–0.6 from N = 4096 to 65536, so 0.5 ± 0.2.
struct GrowthPrior {
    double slope = 0.5;
    double sigma = 0.2;
};

/// The spread (standard deviation) of one replica's ln(seconds per cost unit) between seeds
/// at one size: COMPRESS showed 0.3–0.45 from N = 512 to 8192.
inline constexpr double kSeedSpread = 0.4;

struct SizeEstimate {
    double seconds_per_cost = 0;
    double slope = 0;  ///< the growth used: fit and prior combined
};

/// Seconds per cost unit at size `n` from `sizes` (at least one; several at one N allowed):
/// the weighted least-squares slope of ln rate against ln N (weights: replicas; its variance
/// seed_spread² / Σ w (ln N − mean)²) combined with `prior` by inverse variance (one size
/// measured: the prior alone); then each size's rate carried to n along that slope, and
/// those combined by inverse variance (seed_spread² / replicas + (ln n − ln N)² var(slope)).
SizeEstimate extrapolate_in_n(std::span<const SizeRate> sizes, double n, const GrowthPrior& prior,
                              double seed_spread = kSeedSpread);

}  // namespace jamsim
