// FIRE 2.0 (Guénolé et al., Comput. Mater. Sci. 175, 109584 (2020); Bitzek et al., PRL 97,
// 170201 (2006)), semi-implicit Euler version, unit masses.
#include <algorithm>
#include <cmath>
#include <vector>

#include "jamsim/minimize/minimizer.hpp"
#include "jamsim/minimize/split_positions.hpp"
#include "jamsim/parallel/reduce.hpp"

namespace jamsim {

namespace {

class Fire final : public Minimizer {
  public:
    std::string_view name() const override { return "fire"; }

    MinimizeResult minimize(System& sys, ForceField& forces, const MinimizeCriteria& c) override {
        // Time steps in units of τ = d_s sqrt(m/k_e): the stiffest contact oscillates with
        // ω ≲ sqrt(8), so Δt_max = 1 keeps the dynamics stable; Δt_0 = 0.1 as in LAMMPS.
        constexpr double dt_start = 0.1, dt_max = 1.0, dt_min = 0.002;
        constexpr int n_delay = 20, n_negative_max = 2000;
        constexpr double f_inc = 1.1, f_dec = 0.5, alpha_start = 0.25, f_alpha = 0.99;
        SplitPositions pos(sys, forces, c.split_positions);
        Particles& p = sys.particles;
        const std::size_t n = p.size();
        std::vector<double> vx(n, 0.0), vy(n, 0.0);
        double dt = dt_start, alpha = alpha_start;
        int positive = 0, negative = 0;
        ForceResult f = pos.evaluate();
        ForceResult tallied = f;  // the latest evaluation with energy and virial
        for (std::int64_t it = 0;; ++it) {
            if (c.between_iterations && it > 0 && it % MinimizeCriteria::kIterationsBetweenCalls == 0)
                c.between_iterations();
            const double fmax = pos.max_force();
            if (fmax <= c.force_tol_abs && !f.tallied) f = pos.evaluate(Tally::Full);  // same positions
            if (f.tallied) {
                tallied = f;
                const MinimizeOutcome stop = check_stop(pos, sys, f, c, fmax);
                if (stop != MinimizeOutcome::NotConverged) return summarize(pos, sys, f, stop, it);
            }
            const double fbar = pos.mean_contact_force(tallied);
            if (it >= c.max_iterations || pos.stalled(fmax, fbar, c.stall_iterations) || negative > n_negative_max) {
                if (!f.tallied) f = pos.evaluate(Tally::Full);
                return summarize(pos, sys, f, MinimizeOutcome::NotConverged, it);
            }
            pos.split_if_converging(fmax, fbar);
            const Tally tally = tally_for(it, fmax, fbar, tallied, n, c);
            const double power = blocked_reduce<double>(
                n,
                [&](std::size_t lo, std::size_t hi) {
                    double sum = 0.0;
                    for (std::size_t i = lo; i < hi; ++i) sum += p.fx[i] * vx[i] + p.fy[i] * vy[i];
                    return sum;
                },
                [](double a, double b) { return a + b; });
            if (power > 0.0) {
                ++positive;
                negative = 0;
                if (positive > n_delay) {
                    dt = std::min(dt * f_inc, dt_max);
                    alpha *= f_alpha;
                }
            } else {
                ++negative;
                positive = 0;
                if (it >= n_delay) {  // initial delay: no slow-down in the first steps
                    dt = std::max(dt * f_dec, dt_min);
                    alpha = alpha_start;
                }
                pos.move(-0.5 * dt, vx, vy);  // step back half way: the uphill step
                std::fill(vx.begin(), vx.end(), 0.0);
                std::fill(vy.begin(), vy.end(), 0.0);
            }
            struct Squares {
                double vv = 0.0, ff = 0.0;
            };
            const Squares sq = blocked_reduce<Squares>(
                n,
                [&](std::size_t lo, std::size_t hi) {
                    Squares q;
                    for (std::size_t i = lo; i < hi; ++i) {
                        vx[i] += dt * p.fx[i];
                        vy[i] += dt * p.fy[i];
                        q.vv += vx[i] * vx[i] + vy[i] * vy[i];
                        q.ff += p.fx[i] * p.fx[i] + p.fy[i] * p.fy[i];
                    }
                    return q;
                },
                [](const Squares& a, const Squares& b) {
                    return Squares{a.vv + b.vv, a.ff + b.ff};
                });
            if (sq.ff > 0.0) {  // mix v towards the force direction
                const double scale = alpha * std::sqrt(sq.vv / sq.ff);
                parallel_for(n, [&](std::size_t i) {
                    vx[i] = (1.0 - alpha) * vx[i] + scale * p.fx[i];
                    vy[i] = (1.0 - alpha) * vy[i] + scale * p.fy[i];
                });
            }
            pos.move(dt, vx, vy);
            pos.rebase_if_larger();
            f = pos.evaluate(tally);
        }
    }
};

}  // namespace

std::unique_ptr<Minimizer> make_fire() { return std::make_unique<Fire>(); }

}  // namespace jamsim
