// Non-linear conjugate gradients with a line search on the directional derivative (thesis
// §4.7, Paper I appendix): Polak–Ribière (PR+), and the hybrid of Hestenes–Stiefel and
// Dai–Yuan that jamsim uses by default.
#include <algorithm>
#include <cmath>
#include <vector>

#include "jamsim/minimize/minimizer.hpp"
#include "jamsim/minimize/split_positions.hpp"
#include "jamsim/parallel/reduce.hpp"

namespace jamsim {

namespace {

/// a·b over both components (blocked_reduce: the same bits on any number of threads); in
/// each block four partial sums in a fixed order (four independent chains instead of one
/// long dependency chain of additions).
double dot(std::span<const double> ax, std::span<const double> ay, std::span<const double> bx,
           std::span<const double> by) {
    return blocked_reduce<double>(
        ax.size(),
        [&](std::size_t lo, std::size_t hi) {
            double s[4] = {0, 0, 0, 0};
            const std::size_t m = hi - (hi - lo) % 4;
            for (std::size_t i = lo; i < m; i += 4)
                for (std::size_t k = 0; k < 4; ++k) s[k] += ax[i + k] * bx[i + k] + ay[i + k] * by[i + k];
            for (std::size_t i = m; i < hi; ++i) s[0] += ax[i] * bx[i] + ay[i] * by[i];
            return (s[0] + s[1]) + (s[2] + s[3]);
        },
        [](double a, double b) { return a + b; });
}

/// One pass over the forces after a line search: F·F, F·G (G: the force at its start) and
/// the largest component of F, each in four lanes per block (as dot).
struct ForceSums {
    double ff = 0, fg = 0, fmax = 0;
};
ForceSums force_sums(std::span<const double> fx, std::span<const double> fy, std::span<const double> gx,
                     std::span<const double> gy) {
    return blocked_reduce<ForceSums>(
        fx.size(),
        [&](std::size_t lo, std::size_t hi) {
            double a[4] = {0, 0, 0, 0}, b[4] = {0, 0, 0, 0}, m[4] = {0, 0, 0, 0};
            const std::size_t r = hi - (hi - lo) % 4;
            for (std::size_t i = lo; i < r; i += 4)
                for (std::size_t k = 0; k < 4; ++k) {
                    const double x = fx[i + k], y = fy[i + k];
                    a[k] += x * x + y * y;
                    b[k] += x * gx[i + k] + y * gy[i + k];
                    m[k] = std::max(m[k], std::max(std::abs(x), std::abs(y)));
                }
            for (std::size_t i = r; i < hi; ++i) {
                a[0] += fx[i] * fx[i] + fy[i] * fy[i];
                b[0] += fx[i] * gx[i] + fy[i] * gy[i];
                m[0] = std::max(m[0], std::max(std::abs(fx[i]), std::abs(fy[i])));
            }
            return ForceSums{(a[0] + a[1]) + (a[2] + a[3]), (b[0] + b[1]) + (b[2] + b[3]),
                             std::max(std::max(m[0], m[1]), std::max(m[2], m[3]))};
        },
        [](const ForceSums& u, const ForceSums& v) {
            return ForceSums{u.ff + v.ff, u.fg + v.fg, std::max(u.fmax, v.fmax)};
        });
}

/// d ← F + β d; returns the largest component of the new d.
double update_direction(std::span<double> dx, std::span<double> dy, std::span<const double> fx,
                        std::span<const double> fy, double beta) {
    parallel_for(dx.size(), [&](std::size_t i) {
        dx[i] = fx[i] + beta * dx[i];
        dy[i] = fy[i] + beta * dy[i];
    });
    return parallel_max(dx.size(), [&](std::size_t i) { return std::max(std::abs(dx[i]), std::abs(dy[i])); });
}

/// How the new direction d' = F' + β d mixes in the old one. With g = −F, y = g' − g:
///   PolakRibierePlus:  β = max(0, g'·y / g·g)                         (thesis §4.7)
///   HybridHsDy:        β = max(0, min(g'·y / d·y, g'·g' / d·y))      (Dai & Yuan 2001)
/// With an exact line search d·y = g·g, so Hestenes–Stiefel is Polak–Ribière and Dai–Yuan
/// is Fletcher–Reeves: the hybrid is PR capped by FR, with the denominator measured along
/// the step actually taken. Our line search stops at |φ'(s)| ≤ 0.1 |φ'(0)|, not at the exact
/// minimum, and that correction is what pays: over 32 RAND starts (N = 2048, φ = 0.85, to a
/// largest force of 1e-12) the hybrid needed 22% fewer force evaluations than PR+.
enum class BetaRule { PolakRibierePlus, HybridHsDy };

/// The line search finds a zero of φ'(s) = −F(x + s d)·d: it extrapolates the step by
/// secants (at most 5× per trial, doubling where φ' did not grow) until φ' changes sign, then
/// narrows the bracket by secant steps (safeguarded by bisection) until |φ'(s)| ≤ 0.1 |φ'(0)|,
/// a strong Wolfe condition with a small constant, so the directions stay conjugate. Each φ'
/// costs one force evaluation. The search direction restarts along the force when β ≤ 0 or
/// when d is not a descent direction; no periodic restart, which would reduce CG to steepest
/// descent on the soft, ill-conditioned modes near jamming and after plastic events.
class ConjugateGradient final : public Minimizer {
  public:
    explicit ConjugateGradient(BetaRule rule) : rule_(rule) {}

    std::string_view name() const override { return rule_ == BetaRule::HybridHsDy ? "cg" : "cg-pr"; }

    MinimizeResult minimize(System& sys, ForceField& forces, const MinimizeCriteria& c) override {
        SplitPositions pos(sys, forces, c.split_positions);
        Particles& p = sys.particles;
        const std::size_t n = p.size();
        ForceResult f = pos.evaluate();
        ForceResult tallied = f;  // the latest evaluation with energy and virial
        std::vector<double> dx(p.fx.begin(), p.fx.end()), dy(p.fy.begin(), p.fy.end());
        std::vector<double> gx(n), gy(n);  // the force at the start of the line search
        double step_guess = 0.0, last_slope0 = -1.0;
        // Running sums, so each iteration needs two passes over the disks besides the line
        // search: gg = F·F, slope0 = −F·d, dmax = max |d_i| and fmax = max |F_i| components.
        double gg = dot(p.fx, p.fy, p.fx, p.fy), fmax = pos.max_force(), dmax = fmax;
        double slope0 = -gg;
        auto finish = [&](MinimizeOutcome outcome, std::int64_t it) {
            if (!f.tallied) f = pos.evaluate(Tally::Full);  // same positions: same forces
            return summarize(pos, sys, f, outcome, it);
        };
        // Stopped by the forces alone: the energy tells unjammed from jammed.
        auto settle = [&](std::int64_t it) {
            if (!f.tallied) f = pos.evaluate(Tally::Full);
            return finish(check_stop(pos, sys, f, c, fmax), it);
        };
        for (std::int64_t it = 0;; ++it) {
            if (c.between_iterations && it > 0 && it % MinimizeCriteria::kIterationsBetweenCalls == 0)
                c.between_iterations();
            if (fmax <= c.force_tol_abs) return settle(it);
            if (f.tallied) {
                tallied = f;
                const MinimizeOutcome stop = check_stop(pos, sys, f, c, fmax);
                if (stop != MinimizeOutcome::NotConverged) return finish(stop, it);
            }
            const double fbar = pos.mean_contact_force(tallied);
            if (it >= c.max_iterations || pos.stalled(fmax, fbar, c.stall_iterations))
                return finish(MinimizeOutcome::NotConverged, it);
            pos.split_if_converging(fmax, fbar);
            const Tally tally = tally_for(it, fmax, fbar, tallied, n, c);  // for the line search
            if (slope0 >= 0.0) {  // not a descent direction: restart along the force
                parallel_for(n, [&](std::size_t i) {
                    dx[i] = p.fx[i];
                    dy[i] = p.fy[i];
                });
                slope0 = -gg;
                dmax = fmax;
            }
            if (dmax == 0.0) return settle(it);  // no force at all
            std::swap(gx, p.fx);                 // keep F_old; the line search refills p.fx
            std::swap(gy, p.fy);
            // First trial (Nocedal & Wright eq. 3.60): the same first-order decrease of the
            // energy as the last accepted step, s_prev φ'_prev(0) / φ'(0); at the start a
            // move of 0.01 d_s for the largest component of d; never more than 0.1 d_s.
            double s = step_guess > 0.0 ? step_guess * last_slope0 / slope0 : 0.01 / dmax;
            s = std::min(s, 0.1 / dmax);
            double slope_end = 0.0;  // φ'(s) = −F_new·d at the accepted step
            f = line_search(pos, dx, dy, dmax, slope0, s, tally, slope_end);
            step_guess = s;  // the accepted step
            last_slope0 = slope0;
            pos.rebase_if_larger();
            const ForceSums sums = force_sums(p.fx, p.fy, gx, gy);
            const double ff = sums.ff, fg = sums.fg;
            fmax = sums.fmax;
            const double beta = next_beta(ff, fg, gg, slope0, slope_end);
            dmax = update_direction(dx, dy, p.fx, p.fy, beta);
            // F_new·d_new = ff + β F_new·d_old = ff − β φ'(s).
            slope0 = -(ff - beta * slope_end);
            gg = ff;
        }
    }

  private:
    /// β from F'·F' (ff), F'·F (fg), F·F (gg) and the slopes φ'(0) = −F·d, φ'(s) = −F'·d; in
    /// terms of g = −F: g'·y = ff − fg, d·y = φ'(s) − φ'(0) (> 0 when the search bracketed).
    double next_beta(double ff, double fg, double gg, double slope_start, double slope_end) const {
        if (rule_ == BetaRule::PolakRibierePlus) return gg > 0.0 ? std::max(0.0, (ff - fg) / gg) : 0.0;
        const double dy = slope_end - slope_start;
        if (!(dy > 0.0)) return 0.0;
        return std::max(0.0, std::min(ff - fg, ff) / dy);
    }

    /// Moves the positions to the accepted step along d; `s` is the first trial on entry and
    /// the accepted step on return. Returns the tallied evaluation there.
    /// dmax: the largest component of d (> 0).
    static ForceResult line_search(SplitPositions& pos, std::span<const double> dx, std::span<const double> dy,
                                   double dmax, double slope0, double& s, Tally tally, double& slope_end) {
        Particles& p = pos.system().particles;
        const double target = 0.1 * std::abs(slope0);
        const double cap = 0.1 / dmax;
        double lo = 0.0, slope_lo = slope0;      // φ' < 0 at lo
        double hi = -1.0, slope_hi = 0.0;        // φ' > 0 at hi, once found
        double at = 0.0;                         // where the positions are now
        double prev = 0.0, slope_prev = slope0;  // the last trial, for the secant extrapolation
        ForceResult f;
        for (int k = 0; k < 60; ++k) {
            pos.move(s - at, dx, dy, dmax);
            at = s;
            f = pos.evaluate(tally);
            const double slope = -dot(p.fx, p.fy, dx, dy);
            slope_end = slope;
            if (std::abs(slope) <= target) break;
            if (slope < 0.0) {
                lo = s;
                slope_lo = slope;
            } else {
                hi = s;
                slope_hi = slope;
            }
            if (hi < 0.0) {  // still descending: extrapolate (bounded per trial)
                double next = 2.0 * s;
                if (slope > slope_prev)  // φ' grew: its secant root lies beyond s
                    next = std::min(s - slope * (s - prev) / (slope - slope_prev), s + 4.0 * (s - prev));
                prev = s;
                slope_prev = slope;
                s = std::min(next, s + cap);
                continue;
            }
            // Secant inside [lo, hi], kept away from the ends.
            double next = lo - slope_lo * (hi - lo) / (slope_hi - slope_lo);
            const double width = hi - lo;
            if (!(next > lo + 0.01 * width && next < hi - 0.01 * width)) next = 0.5 * (lo + hi);
            s = next;
            if (width <= 1e-15 * hi) break;  // bracket at round-off: accept
        }
        s = at;  // the accepted step
        return f;
    }

    BetaRule rule_;
};

}  // namespace

std::unique_ptr<Minimizer> make_conjugate_gradient() {
    return std::make_unique<ConjugateGradient>(BetaRule::HybridHsDy);
}

std::unique_ptr<Minimizer> make_polak_ribiere() {
    return std::make_unique<ConjugateGradient>(BetaRule::PolakRibierePlus);
}

}  // namespace jamsim
