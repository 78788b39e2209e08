#include "jamsim/core/system.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "jamsim/core/rng.hpp"

namespace jamsim {

namespace {
double disk_area_sum(const Particles& p) {
    double a = 0.0;
    for (double d : p.diameter) a += std::numbers::pi * d * d / 4.0;
    return a;
}
}  // namespace

double box_side_for(const Particles& p, double phi) { return std::sqrt(disk_area_sum(p) / phi); }

double box_side_for(std::int64_t n, double phi, double size_ratio) {
    const double small = static_cast<double>(size_ratio == 1.0 ? n : n - n / 2);
    const double large = static_cast<double>(size_ratio == 1.0 ? 0 : n / 2);
    return std::sqrt(std::numbers::pi / 4.0 * (small + large * size_ratio * size_ratio) / phi);
}

double packing_fraction(const Particles& p, const Box& box) { return disk_area_sum(p) / box.area(); }

System random_system(std::int64_t n, double phi, SizeMix mix, std::uint64_t seed, std::uint64_t identity) {
    if (n < 2) throw std::invalid_argument("random_system: N must be at least 2");
    if (mix.size_ratio != 1.0 && n % 2 != 0)
        throw std::invalid_argument("random_system: a 50:50 mixture needs an even N, got " + std::to_string(n));
    if (!(phi > 0.0 && phi < 1.0)) throw std::invalid_argument("random_system: phi must lie in (0, 1)");
    Particles p;
    const auto count = static_cast<std::size_t>(n);
    p.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        p.diameter[i] = (i < count / 2 || mix.size_ratio == 1.0) ? 1.0 : mix.size_ratio;
        p.tag[i] = static_cast<std::int32_t>(i);
    }
    const double side = box_side_for(p, phi);
    const RngStream rng(seed, identity, RngPurpose::InitialPositions);
    for (std::size_t i = 0; i < count; ++i) {
        const auto u = rng.uniform2(static_cast<std::uint32_t>(i));
        p.x[i] = u[0] * side;
        p.y[i] = u[1] * side;
    }
    return System{std::move(p), Box(side)};
}

}  // namespace jamsim
