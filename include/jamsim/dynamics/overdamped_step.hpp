#pragma once
// The step shared by the overdamped models (RD0, CD0): positions move with a non-affine
// velocity field v plus the affine shear flow, in sheared coordinates ẋ = v_x − γ v_y,
// ẏ = v_y (thesis eqs. 4.19, 4.22), while γ grows by γ̇ Δt.
#include <span>
#include <vector>

#include "jamsim/core/system.hpp"
#include "jamsim/force/force_field.hpp"
#include "jamsim/parallel/threads.hpp"

namespace jamsim {

/// Scratch of the Heun predictor, shape [N] (kept by the model between steps).
struct OverdampedScratch {
    std::vector<double> x0, y0;
};

/// One step with velocity `scale`·(vx, vy), where (vx, vy) belongs to the current state.
/// Euler: x += Δt·scale (v_x − γ₀ v_y), y += Δt·scale v_y. Heun: the same predictor, then
/// `velocity_at(sys)` returns the velocity spans (vx1, vy1) at the predicted positions and
/// the end-of-step strain γ₁ (it may evaluate forces and solve), and the step is the mean of
/// both slopes. RD0: v = f with scale 1/k_d; CD0: v = u (solved) with scale 1.
template <class VelocityAt>
void overdamped_step(System& sys, ForceField& forces, double dt, double rate, bool heun, double scale,
                     std::span<const double> vx, std::span<const double> vy, OverdampedScratch& scratch,
                     VelocityAt&& velocity_at) {
    Particles& p = sys.particles;
    const double step = dt * scale;
    const double gamma0 = sys.box.strain();
    const double gamma1 = gamma0 + rate * dt;
    if (!heun) {
        drift(p.x, p.y, vx, vy, gamma0, step);
        apply_strain(sys, forces, gamma1);
        return;
    }
    scratch.x0.assign(p.x.begin(), p.x.end());
    scratch.y0.assign(p.y.begin(), p.y.end());
    drift(p.x, p.y, vx, vy, gamma0, step);
    sys.box.set_strain_unwrapped(gamma1);
    const auto v1 = velocity_at(sys);
    // (named spans, not a structured binding: Clang before 16 cannot capture one in a lambda)
    const std::span<const double> vx1 = v1.first, vy1 = v1.second;
    const double half = 0.5 * step;
    parallel_for(p.size(), [&](std::size_t i) {
        p.x[i] = scratch.x0[i] + half * ((vx[i] - gamma0 * vy[i]) + (vx1[i] - gamma1 * vy1[i]));
        p.y[i] = scratch.y0[i] + half * (vy[i] + vy1[i]);
    });
    apply_strain(sys, forces, gamma1);
}

}  // namespace jamsim
