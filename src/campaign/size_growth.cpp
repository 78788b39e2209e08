// A minimisation's throughput at a size not measured (size_growth.hpp).
#include "jamsim/campaign/size_growth.hpp"

#include <cmath>
#include <stdexcept>

namespace jamsim {

SizeEstimate extrapolate_in_n(std::span<const SizeRate> sizes, double n, const GrowthPrior& prior, double seed_spread) {
    if (sizes.empty() || !(n > 0) || !(prior.sigma > 0) || !(seed_spread > 0))
        throw std::invalid_argument("extrapolate_in_n: no sizes, or n, prior.sigma or seed_spread not positive");
    double w_sum = 0, x_mean = 0, y_mean = 0;
    for (const SizeRate& s : sizes) {
        w_sum += s.replicas;
        x_mean += s.replicas * std::log(s.n);
        y_mean += s.replicas * std::log(s.seconds_per_cost);
    }
    x_mean /= w_sum;
    y_mean /= w_sum;
    double sxx = 0, sxy = 0;
    for (const SizeRate& s : sizes) {
        const double dx = std::log(s.n) - x_mean;
        sxx += s.replicas * dx * dx;
        sxy += s.replicas * dx * (std::log(s.seconds_per_cost) - y_mean);
    }
    // The slope: the prior's and (with two sizes or more) the fit's, by inverse variance.
    const double spread2 = seed_spread * seed_spread;
    double precision = 1.0 / (prior.sigma * prior.sigma);
    double weighted = prior.slope * precision;
    if (sxx > 1e-12) {
        const double fit_precision = sxx / spread2;
        weighted += (sxy / sxx) * fit_precision;
        precision += fit_precision;
    }
    const double slope = weighted / precision;
    // The level at n: each size carried along the slope, by inverse variance.
    const double log_n = std::log(n);
    double level = 0, level_weight = 0;
    for (const SizeRate& s : sizes) {
        const double dx = log_n - std::log(s.n);
        const double variance = spread2 / s.replicas + dx * dx / precision;
        level += (std::log(s.seconds_per_cost) + slope * dx) / variance;
        level_weight += 1.0 / variance;
    }
    return {.seconds_per_cost = std::exp(level / level_weight), .slope = slope};
}

}  // namespace jamsim
