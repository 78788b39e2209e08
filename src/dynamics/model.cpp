#include "jamsim/dynamics/model.hpp"

#include "jamsim/parallel/reduce.hpp"

namespace jamsim {

double mean_square_velocity(const Particles& p) {
    const double sum = blocked_reduce<double>(
        p.size(),
        [&](std::size_t lo, std::size_t hi) {
            double s = 0.0;
            for (std::size_t i = lo; i < hi; ++i) s += p.ux[i] * p.ux[i] + p.uy[i] * p.uy[i];
            return s;
        },
        [](double a, double b) { return a + b; });
    return p.size() ? sum / static_cast<double>(p.size()) : 0.0;
}

}  // namespace jamsim
