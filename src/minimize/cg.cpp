// Polak–Ribière non-linear conjugate gradients with a line search on the directional
// derivative (thesis §4.7, Paper I appendix).
#include <algorithm>
#include <cmath>
#include <vector>

#include "jamsim/minimize/minimizer.hpp"
#include "jamsim/minimize/split_positions.hpp"

namespace jamsim {

namespace {

double dot(std::span<const double> ax, std::span<const double> ay, std::span<const double> bx,
           std::span<const double> by) {
    double s = 0.0;
    for (std::size_t i = 0; i < ax.size(); ++i) s += ax[i] * bx[i] + ay[i] * by[i];
    return s;
}

/// PR+ CG. The line search finds a zero of φ'(s) = −F(x + s d)·d: it expands the step until
/// φ' changes sign, then narrows the bracket by secant steps (safeguarded by bisection)
/// until |φ'(s)| ≤ 0.1 |φ'(0)|, a strong Wolfe condition with a small constant, so PR keeps
/// its conjugacy. Each φ' costs one force evaluation. The search direction restarts along
/// the force when β < 0 (PR+) or when d is not a descent direction; no periodic restart,
/// which would reduce CG to steepest descent on the soft, ill-conditioned modes near
/// jamming and after plastic events.
class ConjugateGradient final : public Minimizer {
  public:
    std::string_view name() const override { return "cg"; }

    MinimizeResult minimize(System& sys, ForceField& forces, const MinimizeCriteria& c) override {
        SplitPositions pos(sys, forces, c.split_positions);
        Particles& p = sys.particles;
        const std::size_t n = p.size();
        ForceResult f = pos.evaluate();
        std::vector<double> dx(p.fx.begin(), p.fx.end()), dy(p.fy.begin(), p.fy.end());
        std::vector<double> gx(n), gy(n);  // previous force
        double step_guess = 0.0;
        std::int64_t it = 0;
        for (;; ++it) {
            const MinimizeOutcome stop = check_stop(pos, sys, f, c);
            if (stop != MinimizeOutcome::NotConverged) return summarize(pos, sys, f, stop, it);
            if (it >= c.max_iterations || pos.stalled(pos.max_force(), c.stall_iterations))
                return summarize(pos, sys, f, MinimizeOutcome::NotConverged, it);
            std::copy(p.fx.begin(), p.fx.end(), gx.begin());
            std::copy(p.fy.begin(), p.fy.end(), gy.begin());
            const double gg = dot(gx, gy, gx, gy);
            double slope0 = -dot(gx, gy, dx, dy);  // φ'(0)
            if (slope0 >= 0.0) {  // not a descent direction: restart along the force
                dx = gx;
                dy = gy;
                slope0 = -gg;
            }
            // First trial: the last accepted step, or a move of 0.01 d_s for the largest
            // component of d.
            double dmax = 0.0;
            for (std::size_t i = 0; i < n; ++i) dmax = std::max({dmax, std::abs(dx[i]), std::abs(dy[i])});
            if (dmax == 0.0) return summarize(pos, sys, f, MinimizeOutcome::ForceBalanced, it);
            double s = step_guess > 0.0 ? step_guess : 0.01 / dmax;
            s = std::min(s, 0.1 / dmax);  // never move a disk by more than 0.1 d_s per trial
            f = line_search(pos, dx, dy, slope0, s);
            step_guess = s;
            pos.rebase_if_larger();
            // Polak–Ribière (PR+): β = F_new·(F_new − F_old) / F_old·F_old.
            const double beta_num = dot(p.fx, p.fy, p.fx, p.fy) - dot(p.fx, p.fy, gx, gy);
            double beta = gg > 0.0 ? std::max(0.0, beta_num / gg) : 0.0;
            for (std::size_t i = 0; i < n; ++i) {
                dx[i] = p.fx[i] + beta * dx[i];
                dy[i] = p.fy[i] + beta * dy[i];
            }
        }
    }

  private:
    /// Moves the positions to the accepted step along d; `s` is the first trial on entry and
    /// the accepted step on return. Returns the tallied evaluation there.
    static ForceResult line_search(SplitPositions& pos, std::span<const double> dx,
                                   std::span<const double> dy, double slope0, double& s) {
        Particles& p = pos.system().particles;
        const double target = 0.1 * std::abs(slope0);
        const double cap = 0.1 / std::max(1e-300, max_abs(dx, dy));
        double lo = 0.0, slope_lo = slope0;  // φ' < 0 at lo
        double hi = -1.0, slope_hi = 0.0;    // φ' > 0 at hi, once found
        double at = 0.0;                     // where the positions are now
        ForceResult f;
        for (int k = 0; k < 60; ++k) {
            pos.move(s - at, dx, dy);
            at = s;
            f = pos.evaluate(Tally::Full);
            const double slope = -dot(p.fx, p.fy, dx, dy);
            if (std::abs(slope) <= target) break;
            if (slope < 0.0) {
                lo = s;
                slope_lo = slope;
            } else {
                hi = s;
                slope_hi = slope;
            }
            if (hi < 0.0) {  // still descending: expand (bounded per trial)
                s = std::min(2.0 * s, s + cap);
                continue;
            }
            // Secant inside [lo, hi], kept away from the ends.
            double next = lo - slope_lo * (hi - lo) / (slope_hi - slope_lo);
            const double width = hi - lo;
            if (!(next > lo + 0.01 * width && next < hi - 0.01 * width)) next = 0.5 * (lo + hi);
            s = next;
            if (width <= 1e-15 * hi) break;  // bracket at round-off: accept
        }
        return f;
    }

    static double max_abs(std::span<const double> dx, std::span<const double> dy) {
        double m = 0.0;
        for (std::size_t i = 0; i < dx.size(); ++i) m = std::max({m, std::abs(dx[i]), std::abs(dy[i])});
        return m;
    }
};

} // namespace

std::unique_ptr<Minimizer> make_conjugate_gradient() { return std::make_unique<ConjugateGradient>(); }

} // namespace jamsim
