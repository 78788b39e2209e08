#include "jamsim/dynamics/rd0.hpp"

#include "jamsim/dynamics/overdamped_stability.hpp"
#include "jamsim/parallel/threads.hpp"

namespace jamsim {

void Rd0::advance(System& sys, ForceField& forces, double dt, double rate, std::int64_t) {
    Particles& p = sys.particles;
    overdamped_step(sys, forces, dt, rate, heun_, 1.0 / kd_, p.fx, p.fy, scratch_,
                    [&](System& s) {  // forces at the predicted positions and γ₁
                        fx1_.resize(p.size());
                        fy1_.resize(p.size());
                        forces.compute_at(s.box, p.x, p.y, p.diameter, fx1_, fy1_);
                        return std::pair<std::span<const double>, std::span<const double>>{fx1_, fy1_};
                    });
}

void Rd0::store_velocities(System& sys) const {
    Particles& p = sys.particles;
    parallel_for(p.size(), [&](std::size_t i) {
        p.ux[i] = p.fx[i] / kd_;
        p.uy[i] = p.fy[i] / kd_;
    });
}

Dissipation Rd0::dissipation(const System& sys, const ForceField& /*forces*/, double /*rate*/) const {
    return {.power = kd_ * static_cast<double>(sys.particles.size()) * mean_square_velocity(sys.particles)};
}

namespace {
constexpr std::string_view kRd0Parameters[] = {"dt", "integrator", "kd"};
}

DynamicsInfo rd0_model() {
    return {.name = "RD0",
            .summary = "overdamped, reservoir dissipation -k_d u_i (thesis eq. 4.22)",
            .parameters = kRd0Parameters,
            .evaluations_per_step = [](const ReplicaParams& p) { return p.integrator == "heun" ? 2 : 1; },
            .stable_dt = reservoir_drag_stable_dt,
            .make = [](const ReplicaParams& p, const RandomKey&) -> std::unique_ptr<Model> {
                return std::make_unique<Rd0>(p);
            },
            .stable_dt_basis = reservoir_drag_dt_basis,
            .advisory = [](const ReplicaParams& p) { return overdamped_dt_advisory(p, reservoir_drag_stable_dt); }};
}

}  // namespace jamsim
