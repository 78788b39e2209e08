#pragma once
// Helpers shared by the tests: random configurations and brute-force references that do
// not use the code under test (no Box::min_image, no neighbour list).
#include <cmath>
#include <cstdint>
#include <vector>

#include "jamsim/core/rng.hpp"
#include "jamsim/core/system.hpp"
#include "jamsim/potential/soft_sphere.hpp"

namespace jamsim::testing {

/// Random 50:50 configuration at phi and strain gamma; the first `edge_particles` disks
/// are placed within 0.05 of every edge and corner of the cell (both sides), so pairs
/// straddle every boundary.
inline System random_configuration(std::int64_t n, double phi, double gamma, std::uint64_t seed,
                                   bool straddle = true) {
    System sys = random_system(n, phi, SizeMix{1.4}, seed, 7);
    sys.box.set_strain_unwrapped(gamma);
    if (straddle) {
        const double L = sys.box.side();
        const double eps = 0.02;
        // corners and edge midpoints, each just inside the cell
        const double spots[][2] = {{eps, eps},         {L - eps, eps},     {eps, L - eps},
                                   {L - eps, L - eps}, {L / 2, eps},       {L / 2, L - eps},
                                   {eps, L / 2},       {L - eps, L / 2},   {L / 3, 2 * eps},
                                   {2 * eps, L / 3}};
        std::size_t k = 0;
        for (const auto& s : spots) {
            if (k >= sys.particles.size()) break;
            sys.particles.x[k] = s[0];
            sys.particles.y[k] = s[1];
            ++k;
        }
    }
    return sys;
}

/// Lab separation of j's image (m, n) from i, computed from the definition
/// r = (x + γ y, y) with images at sheared (x + mL, y + nL).
struct Pair {
    double rx, ry;
};
inline Pair image_separation(const System& s, std::size_t i, std::size_t j, int m, int n) {
    const double L = s.box.side(), g = s.box.strain();
    const double dy = s.particles.y[i] - (s.particles.y[j] + n * L);
    const double dx = s.particles.x[i] - (s.particles.x[j] + m * L);
    return {dx + g * dy, dy};
}

/// Brute force over explicit images |m|, |n| ≤ 2: energy, forces, virial, contacts.
struct Reference {
    double energy = 0, vxx = 0, vxy = 0, vyy = 0;
    std::int64_t contacts = 0;
    std::vector<double> fx, fy;
};
inline Reference brute_force(const System& s, const potential::SoftSphere& pot) {
    const std::size_t n = s.particles.size();
    Reference ref;
    ref.fx.assign(n, 0.0);
    ref.fy.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j)
            for (int m = -2; m <= 2; ++m)
                for (int k = -2; k <= 2; ++k) {
                    const Pair r = image_separation(s, i, j, m, k);
                    const double r2 = r.rx * r.rx + r.ry * r.ry;
                    const double d = 0.5 * (s.particles.diameter[i] + s.particles.diameter[j]);
                    if (r2 >= d * d) continue;
                    const auto t = std::visit([&](const auto& e) { return e(r2, d); }, pot);
                    ref.energy += t.energy;
                    ref.fx[i] += t.force_over_r * r.rx;
                    ref.fy[i] += t.force_over_r * r.ry;
                    ref.fx[j] -= t.force_over_r * r.rx;
                    ref.fy[j] -= t.force_over_r * r.ry;
                    ref.vxx += t.force_over_r * r.rx * r.rx;
                    ref.vxy += t.force_over_r * r.rx * r.ry;
                    ref.vyy += t.force_over_r * r.ry * r.ry;
                    ++ref.contacts;
                }
    return ref;
}

} // namespace jamsim::testing
