// Jamming protocols through the replica runner (the path campaigns take): the jamming
// probability of RAND quenches, and quasistatic shear's independence of the strain step.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "jamsim/run/replica.hpp"
#include "support/statistics.hpp"

using namespace jamsim;

namespace {

/// An estimate and its standard error.
struct Probability {
    double p, error;
};

/// Width of the jamming transition from P_J(φ) read as a cumulative distribution of φ_J over
/// configurations: the standard deviation of φ_J with the probability mass of each rise
/// P_J(φ_k) − P_J(φ_{k−1}) placed at the interval's midpoint.
double transition_width(const std::vector<double>& phis, const std::vector<double>& pj) {
    double m1 = 0, m2 = 0, mass = 0;
    for (std::size_t k = 1; k < phis.size(); ++k) {
        const double w = pj[k] - pj[k - 1], mid = 0.5 * (phis[k] + phis[k - 1]);
        m1 += w * mid;
        m2 += w * mid * mid;
        mass += w;
    }
    if (mass <= 0) return 0;
    m1 /= mass;
    return std::sqrt(std::max(0.0, m2 / mass - m1 * m1));
}

/// Jammed (1) or not (0) for each seed at each φ.
std::vector<std::vector<int>> outcomes(std::int64_t n, const std::vector<double>& phis, int seeds) {
    std::vector<std::vector<int>> out;
    for (double phi : phis) {
        out.emplace_back();
        for (int s = 1; s <= seeds; ++s) {
            ReplicaParams p;
            p.model = "RAND";
            p.n = n;
            p.phi = phi;
            p.rate = 0.0;
            p.seed = static_cast<std::uint64_t>(s);
            out.back().push_back(run_replica(p).series[0].jammed == 1.0);
        }
    }
    return out;
}

/// Width and its bootstrap standard error (resampling the seeds at every φ independently).
Probability width_with_error(const std::vector<double>& phis, const std::vector<std::vector<int>>& jammed) {
    auto curve = [&](const std::vector<std::vector<int>>& j) {
        std::vector<double> pj;
        for (const auto& row : j) {
            double sum = 0;
            for (int v : row) sum += v;
            pj.push_back(sum / static_cast<double>(row.size()));
        }
        return pj;
    };
    const double w = transition_width(phis, curve(jammed));
    std::mt19937_64 rng(12345);
    std::vector<double> boot;
    for (int b = 0; b < 400; ++b) {
        std::vector<std::vector<int>> r;
        for (const auto& row : jammed) {
            std::uniform_int_distribution<std::size_t> pick(0, row.size() - 1);
            r.emplace_back();
            for (std::size_t k = 0; k < row.size(); ++k) r.back().push_back(row[pick(rng)]);
        }
        boot.push_back(transition_width(phis, curve(r)));
    }
    double m = 0, v = 0;
    for (double x : boot) m += x / static_cast<double>(boot.size());
    for (double x : boot) v += (x - m) * (x - m) / static_cast<double>(boot.size() - 1);
    return {w, std::sqrt(v)};
}

}  // namespace

// P_J(φ) of RAND quenches rises monotonically through [0.80, 0.86], and the rise is
// narrower for N = 256 than for N = 64 (the width shrinks with N, Paper I).
TEST(JammingProbability, MonotoneAndNarrowerForLargerN) {
    const std::vector<double> phis{0.80, 0.81, 0.82, 0.825, 0.83, 0.835, 0.84, 0.845, 0.85, 0.86};
    const int seeds = 40;
    const auto small = outcomes(64, phis, seeds), large = outcomes(256, phis, seeds);
    for (const auto* j : {&small, &large}) {
        std::vector<Probability> pj;
        for (const auto& row : *j) {
            double sum = 0;
            for (int v : row) sum += v;
            const double p = sum / seeds;
            const double var = std::max(p * (1 - p), (1.0 / seeds) * (1 - 1.0 / seeds));
            pj.push_back({p, std::sqrt(var / seeds)});
        }
        for (std::size_t k = 0; k < phis.size(); ++k)
            std::printf("N %d phi %.3f P_J %.3f +- %.3f\n", j == &small ? 64 : 256, phis[k], pj[k].p, pj[k].error);
        for (std::size_t k = 1; k < phis.size(); ++k)  // monotone within 3 standard errors
            EXPECT_GE(pj[k].p - pj[k - 1].p, -3 * std::hypot(pj[k].error, pj[k - 1].error)) << "phi " << phis[k];
        EXPECT_EQ(pj.back().p, 1.0) << "every RAND quench at phi = 0.86 jams";
    }
    const auto ws = width_with_error(phis, small), wl = width_with_error(phis, large);
    std::printf("width of the transition: N = 64 %.4f +- %.4f, N = 256 %.4f +- %.4f\n", ws.p, ws.error, wl.p, wl.error);
    EXPECT_GT(ws.p - wl.p, 3 * std::hypot(ws.error, wl.error));
}

// Quasistatic shear: halving the strain step leaves ⟨p⟩ and ⟨σ⟩ unchanged within errors.
TEST(QuasistaticShear, StrainStepIndependence) {
    auto run = [](double step, int seed) {
        ReplicaParams p;
        p.model = "QS";
        p.n = 64;
        p.phi = 0.86;
        p.rate = 0.0;
        p.strain = 1.0;
        p.transient = 0.2;
        p.strain_step = step;
        p.sample_interval = 0.01;
        p.seed = static_cast<std::uint64_t>(seed);
        const ReplicaResult r = run_replica(p);
        double sp = 0, ss = 0;
        int k = 0;
        for (std::size_t i = 0; i < r.series.size(); ++i)
            if (r.series[i].strain >= p.transient) {
                sp += r.series[i].pressure;
                ss += r.series[i].shear_stress;
                ++k;
            }
        return std::pair{sp / k, ss / k};
    };
    std::vector<double> p1, p2, s1, s2;
    for (int seed = 1; seed <= 8; ++seed) {
        const auto a = run(2e-3, seed), b = run(1e-3, seed);
        p1.push_back(a.first);
        s1.push_back(a.second);
        p2.push_back(b.first);
        s2.push_back(b.second);
    }
    using jamsim::testing::mean_and_error;
    const auto P1 = mean_and_error(p1), P2 = mean_and_error(p2), S1 = mean_and_error(s1), S2 = mean_and_error(s2);
    std::printf("QS: <p> %.5f +- %.5f (dgamma 2e-3) vs %.5f +- %.5f (1e-3); <sigma> %.5f +- %.5f vs %.5f +- %.5f\n",
                P1.mean, P1.error, P2.mean, P2.error, S1.mean, S1.error, S2.mean, S2.error);
    EXPECT_GT(S1.mean, 0.0) << "a sheared jammed solid carries a positive yield stress";
    EXPECT_LE(std::abs(P1.mean - P2.mean), 3 * std::hypot(P1.error, P2.error));
    EXPECT_LE(std::abs(S1.mean - S2.mean), 3 * std::hypot(S1.error, S2.error));
}

// Cooling (Paper I): thermal preparation before the quench finds deeper minima than the
// infinite-temperature RAND quench, and slower cooling deeper still; at φ = 0.86 the
// quenched pressure and energy fall with the cooling time (means over 12 seeds, 3σ apart).
TEST(Cooling, SlowerCoolingGivesDeeperMinima) {
    auto quenched = [](const std::string& model, double cooling_time) {
        std::vector<double> p, e;
        for (int seed = 1; seed <= 12; ++seed) {
            ReplicaParams q;
            q.model = model;
            q.n = 64;
            q.phi = 0.86;
            q.rate = 0.0;
            q.temperature = 1e-3;
            q.cooling_time = cooling_time;
            q.seed = static_cast<std::uint64_t>(seed);
            const ReplicaResult r = run_replica(q);
            EXPECT_EQ(r.series[0].jammed, 1.0);
            p.push_back(r.series[0].pressure);
            e.push_back(r.series[0].energy_per_particle);
        }
        return std::pair{jamsim::testing::mean_and_error(p), jamsim::testing::mean_and_error(e)};
    };
    const auto [p_rand, e_rand] = quenched("RAND", 1.0);
    const auto [p_fast, e_fast] = quenched("COOL", 1e3);
    const auto [p_slow, e_slow] = quenched("COOL", 2e4);
    std::printf("quenched <p>: RAND %.5f +- %.5f, cooled over 1e3 %.5f +- %.5f, over 2e4 %.5f +- %.5f\n", p_rand.mean,
                p_rand.error, p_fast.mean, p_fast.error, p_slow.mean, p_slow.error);
    std::printf("quenched <E/N>: RAND %.3e +- %.1e, 1e3 %.3e +- %.1e, 2e4 %.3e +- %.1e\n", e_rand.mean, e_rand.error,
                e_fast.mean, e_fast.error, e_slow.mean, e_slow.error);
    EXPECT_GT(p_rand.mean - p_slow.mean, 3 * std::hypot(p_rand.error, p_slow.error));
    EXPECT_GT(e_rand.mean - e_slow.mean, 3 * std::hypot(e_rand.error, e_slow.error));
    EXPECT_GT(p_fast.mean - p_slow.mean, 0.0) << "slower cooling should not give a higher pressure";
}

// Pressure distribution over configurations at fixed φ (Paper III): at φ = 0.86 every RAND
// quench jams, and the relative width std(p)/⟨p⟩ of the distribution (60 configurations
// each) narrows with N (as N^{-1/2} for a self-averaging quantity): it must be smaller for
// N = 512 than for N = 64 by more than 3 bootstrap standard errors.
TEST(PressureDistribution, NarrowsWithN) {
    auto relative_width = [](std::int64_t n) {
        std::vector<double> p;
        for (int seed = 1; seed <= 60; ++seed) {
            ReplicaParams q;
            q.model = "RAND";
            q.n = n;
            q.phi = 0.86;
            q.rate = 0.0;
            q.seed = static_cast<std::uint64_t>(seed);
            const ReplicaResult r = run_replica(q);
            EXPECT_EQ(r.series[0].jammed, 1.0);
            p.push_back(r.series[0].pressure);
        }
        auto width = [](const std::vector<double>& v) {
            double m = 0, s = 0;
            for (double x : v) m += x / static_cast<double>(v.size());
            for (double x : v) s += (x - m) * (x - m) / static_cast<double>(v.size() - 1);
            return std::sqrt(s) / m;
        };
        std::mt19937_64 rng(7);
        std::uniform_int_distribution<std::size_t> pick(0, p.size() - 1);
        std::vector<double> boot;
        for (int b = 0; b < 400; ++b) {
            std::vector<double> r;
            for (std::size_t k = 0; k < p.size(); ++k) r.push_back(p[pick(rng)]);
            boot.push_back(width(r));
        }
        const auto e = jamsim::testing::mean_and_error(boot);
        return Probability{width(p), e.error * std::sqrt(static_cast<double>(boot.size()))};
    };
    const Probability small = relative_width(64), large = relative_width(512);
    std::printf("std(p)/<p> at phi = 0.86: N = 64 %.3f +- %.3f, N = 512 %.3f +- %.3f\n", small.p, small.error, large.p,
                large.error);
    EXPECT_GT(small.p - large.p, 3 * std::hypot(small.error, large.error));
}
