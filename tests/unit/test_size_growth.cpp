// extrapolate_in_n (size_growth.hpp): a minimisation's seconds per cost unit at a size not
// measured, the growth fitted to the sizes measured weighed against the prior.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "jamsim/campaign/size_growth.hpp"

namespace {

using jamsim::extrapolate_in_n;
using jamsim::GrowthPrior;
using jamsim::SizeRate;

// One size measured: nothing to fit, so the prior's growth alone.
TEST(SizeGrowth, OneSizeTakesThePriorsGrowth) {
    const std::vector<SizeRate> sizes{{.n = 1024, .seconds_per_cost = 3e-7, .replicas = 3}};
    const auto e = extrapolate_in_n(sizes, 8192, GrowthPrior{.slope = 0.5, .sigma = 0.2});
    EXPECT_DOUBLE_EQ(e.slope, 0.5);
    EXPECT_NEAR(e.seconds_per_cost, 3e-7 * std::sqrt(8.0), 1e-12 * 3e-7);
}

// Many replicas per size: the fit's variance (seed spread² / Σ w (ln N − mean)²) is tiny, so
// the data's growth (N^0.8 here, not the prior's) and level hold.
TEST(SizeGrowth, WellMeasuredSizesOverrideThePrior) {
    std::vector<SizeRate> sizes;
    for (const double n : {512.0, 1024.0, 2048.0})
        sizes.push_back({.n = n, .seconds_per_cost = 2e-7 * std::pow(n / 512, 0.8), .replicas = 1e8});
    const auto e = extrapolate_in_n(sizes, 16384, GrowthPrior{});
    EXPECT_NEAR(e.slope, 0.8, 1e-6);
    EXPECT_NEAR(e.seconds_per_cost / (2e-7 * std::pow(32.0, 0.8)), 1.0, 1e-5);
}

// Few replicas: the combination by hand. Two sizes, 3 replicas each, rate ×4 from N = 512 to
// 1024 (fitted slope ln 4 / ln 2 = 2); seed spread 0.4. Σ w (x − x̄)² = 6 (ln 2 / 2)² =
// 0.72068, so the fit's precision is 0.72068 / 0.16 = 4.5043 against the prior's 1 / 0.2² =
// 25: slope (2 · 4.5042 + 0.5 · 25) / 29.5042 = 0.72900, variance 1 / 29.5042 = 0.033893.
// At N = 4096 the size 512 (Δ = ln 8 = 2.07944) says ln r + 1.51591 with variance
// 0.16 / 3 + 2.07944² · 0.033893 = 0.19989, the size 1024 (Δ = ln 4) says ln r + ln 4 +
// 1.01061 = ln r + 2.39690 with variance 0.05333 + 1.92181 · 0.033893 = 0.11847; by inverse
// variance ln r + 2.06906, i.e. 7.9174 r.
TEST(SizeGrowth, FewReplicasCombineFitAndPriorByTheirVariances) {
    const double r = 1e-7;
    const std::vector<SizeRate> sizes{{.n = 512, .seconds_per_cost = r, .replicas = 3},
                                      {.n = 1024, .seconds_per_cost = 4 * r, .replicas = 3}};
    const auto e = extrapolate_in_n(sizes, 4096, GrowthPrior{.slope = 0.5, .sigma = 0.2}, 0.4);
    EXPECT_NEAR(e.slope, 0.72900, 1e-5);
    EXPECT_NEAR(e.seconds_per_cost / r, 7.9174, 1e-3);
}

// The level leans on the better-measured and the nearer size: a single outlying replica at
// the size nearest the target moves the estimate less than three replicas would.
TEST(SizeGrowth, AnOutlyingSingleReplicaCountsLessThanThree) {
    const auto at_8192 = [](double replicas_at_2048) {
        const std::vector<SizeRate> sizes{{.n = 512, .seconds_per_cost = 1e-7, .replicas = 3},
                                          {.n = 1024, .seconds_per_cost = 1.4e-7, .replicas = 3},
                                          {.n = 2048, .seconds_per_cost = 4e-7, .replicas = replicas_at_2048}};
        return extrapolate_in_n(sizes, 8192, GrowthPrior{}).seconds_per_cost;
    };
    const double without =
        extrapolate_in_n(std::vector<SizeRate>{{.n = 512, .seconds_per_cost = 1e-7, .replicas = 3},
                                               {.n = 1024, .seconds_per_cost = 1.4e-7, .replicas = 3}},
                         8192, GrowthPrior{})
            .seconds_per_cost;
    EXPECT_GT(at_8192(1), without);
    EXPECT_GT(at_8192(3), at_8192(1));
}

TEST(SizeGrowth, RefusesWhatItCannotUse) {
    const std::vector<SizeRate> none;
    EXPECT_THROW(extrapolate_in_n(none, 1024, GrowthPrior{}), std::invalid_argument);
    const std::vector<SizeRate> one{{.n = 512, .seconds_per_cost = 1e-7, .replicas = 1}};
    EXPECT_THROW(extrapolate_in_n(one, 0, GrowthPrior{}), std::invalid_argument);
    EXPECT_THROW(extrapolate_in_n(one, 1024, GrowthPrior{.slope = 0.5, .sigma = 0}), std::invalid_argument);
}

}  // namespace
