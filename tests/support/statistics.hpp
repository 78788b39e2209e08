#pragma once
// Mean and standard error over independent samples (one per seed): the error estimate the
// statistical tests use.
#include <cmath>
#include <vector>

namespace jamsim::testing {

struct Estimate {
    double mean, error;
};

inline Estimate mean_and_error(const std::vector<double>& v) {
    double m = 0, s2 = 0;
    for (double x : v) m += x / static_cast<double>(v.size());
    for (double x : v) s2 += (x - m) * (x - m) / static_cast<double>(v.size() - 1);
    return {m, std::sqrt(s2 / static_cast<double>(v.size()))};
}

}  // namespace jamsim::testing
