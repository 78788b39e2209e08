#include "jamsim/protocols/preparation.hpp"

#include <cmath>
#include <numbers>

#include "jamsim/protocols/jamming.hpp"

namespace jamsim {

std::int64_t cooling_steps(const CoolingSchedule& schedule) {
    return static_cast<std::int64_t>(std::ceil(schedule.duration / schedule.dt - 1e-9));
}

std::int64_t shear_steps(double strain, double strain_step) {
    return static_cast<std::int64_t>(std::ceil(strain / strain_step - 1e-9));
}

std::int64_t cool(System& sys, ForceField& forces, const CoolingSchedule& schedule, const RngStream& noise,
                  std::int64_t first_step, const BeforeStep& before) {
    const std::int64_t steps = cooling_steps(schedule);
    const double dt = schedule.dt, kd = schedule.kd;
    Particles& q = sys.particles;
    for (std::int64_t step = first_step; step < steps; ++step) {
        if (before && step > first_step) before(step, step - first_step);
        const double t = 1.0 - static_cast<double>(step) / static_cast<double>(steps);
        const double amplitude = std::sqrt(2.0 * schedule.temperature * t * dt / kd);
        forces.compute(sys, Tally::ForcesOnly);
        for (std::size_t i = 0; i < q.size(); ++i) {
            const auto u = noise.uniform2(static_cast<std::uint32_t>(q.tag[i]), static_cast<std::uint32_t>(step));
            const double r = std::sqrt(-2.0 * std::log1p(-u[0])), a = 2.0 * std::numbers::pi * u[1];  // Box–Muller
            // The step is drawn in the lab frame; the positions move by its sheared image.
            const Vec2 d = sys.box.sheared(dt * q.fx[i] / kd + amplitude * r * std::cos(a),
                                           dt * q.fy[i] / kd + amplitude * r * std::sin(a));
            q.x[i] += d.x;
            q.y[i] += d.y;
        }
    }
    return steps - first_step;
}

std::int64_t shear_quasistatically(System& sys, ForceField& forces, Minimizer& minimizer,
                                   const MinimizeCriteria& criteria, double strain, double strain_step,
                                   std::int64_t first_step, const BeforeStep& before) {
    const std::int64_t steps = shear_steps(strain, strain_step);
    std::int64_t evaluations = 0;
    for (std::int64_t step = first_step; step < steps; ++step) {
        if (before && step > first_step) before(step, evaluations);
        evaluations += quench(sys, forces, minimizer, criteria).minimum.force_evaluations;
        apply_strain(sys, forces, sys.box.strain() + strain_step);
    }
    return evaluations;
}

}  // namespace jamsim
