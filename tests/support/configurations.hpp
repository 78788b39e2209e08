#pragma once
// Helpers shared by the tests: random configurations and brute-force references that do
// not use the code under test (no Box::min_image, no neighbour list).
#include <cmath>
#include <cstdint>
#include <set>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "jamsim/core/rng.hpp"
#include "jamsim/core/system.hpp"
#include "jamsim/potential/soft_sphere.hpp"

namespace jamsim::testing {

/// Random 50:50 configuration at phi and strain gamma; the first `edge_particles` disks
/// are placed within 0.05 of every edge and corner of the cell (both sides), so pairs
/// straddle every boundary.
inline System random_configuration(std::int64_t n, double phi, double gamma, std::uint64_t seed, bool straddle = true) {
    System sys = random_system(n, phi, SizeMix{1.4}, seed, 7);
    sys.box.set_strain_unwrapped(gamma);
    if (straddle) {
        const double L = sys.box.side();
        const double eps = 0.02;
        // corners and edge midpoints, each just inside the cell
        const double spots[][2] = {{eps, eps},       {L - eps, eps},   {eps, L - eps}, {L - eps, L - eps},
                                   {L / 2, eps},     {L / 2, L - eps}, {eps, L / 2},   {L - eps, L / 2},
                                   {L / 3, 2 * eps}, {2 * eps, L / 3}};
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

/// `sys` randomly moved for trial `trial` of a Verlet-rule property test: every disk
/// displaced by up to ±s/2 in x and y (s uniform in [0, max_step) per trial), and the strain
/// set uniformly within strain ± spread/2.
inline System randomly_moved(const System& sys, const RngStream& rng, std::uint32_t trial, double max_step,
                             double strain, double spread) {
    System moved = sys;
    const double scale = max_step * rng.uniform2(trial, 999)[0];
    for (std::size_t i = 0; i < moved.particles.size(); ++i) {
        const auto u = rng.uniform2(trial, static_cast<std::uint32_t>(i));
        moved.particles.x[i] += scale * (u[0] - 0.5);
        moved.particles.y[i] += scale * (u[1] - 0.5);
    }
    moved.box.set_strain_unwrapped(strain + spread * (rng.uniform2(trial, 998)[0] - 0.5));
    return moved;
}

/// Unordered pairs (i < j).
using PairSet = std::set<std::pair<std::size_t, std::size_t>>;

/// Pairs with some image closer than `extra` + d_ij (brute force over images |m|, |n| ≤ 2).
inline PairSet pairs_within(const System& s, double extra) {
    PairSet out;
    for (std::size_t i = 0; i < s.particles.size(); ++i)
        for (std::size_t j = i + 1; j < s.particles.size(); ++j)
            for (int m = -2; m <= 2; ++m)
                for (int n = -2; n <= 2; ++n) {
                    const auto r = image_separation(s, i, j, m, n);
                    const double range = 0.5 * (s.particles.diameter[i] + s.particles.diameter[j]) + extra;
                    if (r.rx * r.rx + r.ry * r.ry < range * range) out.insert({i, j});
                }
    return out;
}

/// The pairs of a NeighborList or SubList (owner/neighbour entries); a pair listed twice
/// fails the calling test.
template <class List> PairSet listed_pairs(const List& list) {
    PairSet s;
    for (std::size_t k = 0; k < list.size(); ++k) {
        const auto i = static_cast<std::size_t>(list.owner()[k]);
        const auto j = static_cast<std::size_t>(list.neighbor()[k]);
        EXPECT_TRUE(s.insert({std::min(i, j), std::max(i, j)}).second) << "pair listed twice";
    }
    return s;
}

/// Whether `list` holds every pair of `s` that touches (brute force over images).
template <class List> bool lists_every_contact(const List& list, const System& s) {
    const PairSet listed = listed_pairs(list);
    for (const auto& pair : pairs_within(s, 0.0))
        if (!listed.count(pair)) return false;
    return true;
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

}  // namespace jamsim::testing
