#include "jamsim/core/particles.hpp"

#include <algorithm>

#include "jamsim/parallel/threads.hpp"

namespace jamsim {

namespace {
template <class T> void apply_order(std::vector<T>& a, std::span<const std::int32_t> order) {
    std::vector<T> out(a.size());
    parallel_for(order.size(), [&](std::size_t k) { out[k] = a[static_cast<std::size_t>(order[k])]; });
    a.swap(out);
}
}  // namespace

void Particles::permute(std::span<const std::int32_t> order) {
    apply_order(x, order);
    apply_order(y, order);
    apply_order(diameter, order);
    apply_order(fx, order);
    apply_order(fy, order);
    apply_order(tag, order);
    apply_order(ux, order);
    apply_order(uy, order);
}

double max_diameter(const Particles& p) {
    double m = 0.0;
    for (double d : p.diameter) m = std::max(m, d);
    return m;
}

}  // namespace jamsim
