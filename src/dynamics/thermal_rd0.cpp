// RD0T: RD0 at temperature T, i.e. overdamped Langevin dynamics of the disks under shear
// with reservoir dissipation (thesis §4.5.2 with thermal noise; the dynamics the COOL
// protocol uses at fixed strain). In the lab frame
//   dr_i = (γ̇ y_i x̂ + f_i^el / k_d) dt + sqrt(2 T / k_d) dW_i,
// integrated by Euler–Maruyama: each step adds f Δt/k_d and a Gaussian displacement of
// variance 2 T Δt / k_d per component, both mapped to sheared coordinates. The noise of disk i
// at step n is keyed by (seed, replica identity, disk tag, n), so a run does not depend on
// the order of disks in memory or on how replicas are scheduled.
// Sampled velocities are the drift f/k_d (the noise has no velocity); dissipated_power is
// k_d ⟨|f/k_d|²⟩, which in steady state balances the input power plus the thermal term
// (T/k_d) Σ ∇²V.
#include <cmath>
#include <numbers>

#include "jamsim/core/rng.hpp"
#include "jamsim/dynamics/overdamped_stability.hpp"
#include "jamsim/dynamics/rd0.hpp"

#include "jamsim/parallel/threads.hpp"

namespace jamsim {

namespace {

class ThermalRd0 final : public Model {
  public:
    ThermalRd0(const ReplicaParams& p, const RandomKey& key)
        : drift_model_(p), kd_(p.kd), temperature_(p.temperature), noise_(key, RngPurpose::ThermalNoise) {}

    void advance(System& sys, ForceField& forces, double dt, double rate, std::int64_t step) override {
        Particles& q = sys.particles;
        const double amplitude = std::sqrt(2.0 * temperature_ * dt / kd_);
        parallel_for(q.size(), [&](std::size_t i) {
            const auto u = noise_.uniform2(static_cast<std::uint32_t>(q.tag[i]), static_cast<std::uint32_t>(step));
            // Box–Muller: two independent unit Gaussians from two uniforms.
            const double r = std::sqrt(-2.0 * std::log1p(-u[0])), a = 2.0 * std::numbers::pi * u[1];
            const Vec2 d = sys.box.sheared(dt * q.fx[i] / kd_ + amplitude * r * std::cos(a),
                                           dt * q.fy[i] / kd_ + amplitude * r * std::sin(a));
            q.x[i] += d.x;
            q.y[i] += d.y;
        });
        apply_strain(sys, forces, sys.box.strain() + rate * dt);
    }

    void store_velocities(System& sys) const override { drift_model_.store_velocities(sys); }

    Dissipation dissipation(const System& sys, const ForceField& forces, double rate) const override {
        return drift_model_.dissipation(sys, forces, rate);
    }

  private:
    Rd0 drift_model_;  // the deterministic part: velocities and dissipation of RD0
    double kd_, temperature_;
    RngStream noise_;
};

constexpr std::string_view kParameters[] = {"dt", "kd", "temperature"};

}  // namespace

DynamicsInfo thermal_rd0_model() {
    return {.name = "RD0T",
            .summary = "RD0 at temperature T: overdamped Langevin dynamics under shear "
                       "(Euler-Maruyama)",
            .parameters = kParameters,
            .evaluations_per_step = [](const ReplicaParams&) { return 1; },
            // The drift is RD0's Euler step; the noise does not change its stability.
            .stable_dt = reservoir_drag_stable_dt,
            .make = [](const ReplicaParams& p, const RandomKey& key) -> std::unique_ptr<Model> {
                return std::make_unique<ThermalRd0>(p, key);
            },
            .stable_dt_basis = reservoir_drag_dt_basis,
            .advisory = [](const ReplicaParams& p) { return overdamped_dt_advisory(p, reservoir_drag_stable_dt); }};
}

}  // namespace jamsim
