#include "jamsim/dynamics/model.hpp"

namespace jamsim {

double mean_square_velocity(const Particles& p) {
    double sum = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) sum += p.ux[i] * p.ux[i] + p.uy[i] * p.uy[i];
    return p.size() ? sum / static_cast<double>(p.size()) : 0.0;
}

} // namespace jamsim
