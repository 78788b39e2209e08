#include <cmath>
#include <stdexcept>

#include "jamsim/observe/velocity_correlation.hpp"
#include "jamsim/run/replica.hpp"
#include "replica_run.hpp"

namespace jamsim {

FinalConfiguration final_configuration(const System& sys) {
    const Particles& p = sys.particles;
    const std::size_t n = p.size();
    FinalConfiguration out{.x = std::vector<double>(n),
                           .y = std::vector<double>(n),
                           .diameter = std::vector<double>(n),
                           .box_side = sys.box.side(),
                           .box_strain = sys.box.strain()};
    for (std::size_t k = 0; k < n; ++k) {
        const auto t = static_cast<std::size_t>(p.tag[k]);
        double xw = p.x[k], yw = p.y[k];
        sys.box.wrap_into_cell(xw, yw);
        out.x[t] = xw;
        out.y[t] = yw;
        out.diameter[t] = p.diameter[k];
    }
    return out;
}

System initial_system(const ReplicaParams& p) {
    const RandomKey key = random_key(p);
    return random_system(p.n, p.phi, SizeMix{p.size_ratio}, key.seed, key.identity);
}

System start_system(const ReplicaParams& p) {
    System sys = initial_system(p);
    if (const auto relax = model_of(p).relax_start) relax(sys, p);
    return sys;
}

ReplicaResult run_replica(const ReplicaParams& p, const RunContext& context) {
    const auto errors = validate(p);
    if (!errors.empty())
        throw std::invalid_argument("replica parameter " + errors.front().key + " = " + errors.front().value +
                                    ": allowed " + errors.front().allowed);
    if (!p.initial.empty() && !context.initial && !context.resume)
        throw std::invalid_argument("replica parameter initial = " + p.initial +
                                    ": its configuration was not read (RunContext::initial)");
    return model_of(p).run(p, context);
}

ReplicaResult run_dynamics(const ReplicaParams& p, const RunContext& context) {
    ReplicaRun run(p, context);
    System& sys = run.system();
    ReplicaResult& result = run.result;
    const ModelInfo& info = model_of(p);
    auto model = info.make(p, random_key(p));
    const Schedule plan = schedule_of(p);
    const double inv_n = 1.0 / static_cast<double>(p.n);
    VelocityCorrelation correlation(sys.box.side());
    if (run.resumed()) correlation.restore(run.resumed()->correlation);
    const std::int64_t evals_per_step = evaluations_per_step(p);
    const SampleHook& after_sample = context.after_sample;

    for (std::int64_t step = run.first_step();; ++step) {
        if (run.checkpoint_step(step, plan.steps, &correlation)) model = info.make(p, random_key(p));
        const bool sample_now = step % plan.sample_every == 0;
        // Models that evaluate the new state's forces themselves (RD's splitting) need the
        // driver's evaluation only for the first state and for the tallies of a sample.
        ForceResult f{};
        if (step == 0 || sample_now || !model->leaves_forces_current()) {
            f = run.forces.compute(sys, sample_now ? Tally::Full : Tally::ForcesOnly);
            if (step > 0 && model->leaves_forces_current()) result.force_evaluations += 1;
        }
        model->prepare(sys, run.forces, p.rate);
        if (sample_now) {
            const double t = static_cast<double>(step) * p.dt;
            model->store_velocities(sys);
            const Dissipation dis = model->dissipation(sys, run.forces, p.rate);
            const double sigma = f.shear_stress(sys.box);
            const double sigma_total = sigma + dis.shear_stress + dis.shear_stress_kinetic;
            const Sample s{.time = t,
                           .strain = p.rate * t,
                           .energy_per_particle = f.energy * inv_n,
                           .pressure = f.pressure(sys.box),
                           .shear_stress = sigma,
                           .contact_number = 2.0 * static_cast<double>(f.contacts) * inv_n,
                           .nonaffine_velocity_sq = mean_square_velocity(sys.particles),
                           .pressure_dissipative = dis.pressure,
                           .shear_stress_dissipative = dis.shear_stress,
                           .input_power = sigma_total * p.rate * sys.box.area() * inv_n,
                           .dissipated_power = dis.power * inv_n,
                           .kinetic_energy_per_particle = dis.kinetic_energy * inv_n,
                           .pressure_kinetic = dis.pressure_kinetic,
                           .shear_stress_kinetic = dis.shear_stress_kinetic,
                           .solver_iterations = model->solver_iterations(),
                           .packing_fraction = p.phi};
            if (!std::isfinite(s.energy_per_particle) || !std::isfinite(s.pressure))
                throw std::runtime_error("non-finite state at t = " + show_value(t) + " (time step too large?)");
            result.series.push(s);
            const bool steady = p.rate > 0.0 ? s.strain >= p.transient : s.time >= p.transient;
            if (steady) correlation.accumulate(sys);
            if (after_sample)
                after_sample(static_cast<double>(step) / static_cast<double>(std::max<std::int64_t>(plan.steps, 1)));
        }
        if (plan.frame_every > 0 && step % plan.frame_every == 0 && context.on_frame) {
            const double t = static_cast<double>(step) * p.dt;
            context.on_frame(step / plan.frame_every, p.rate > 0.0 ? p.rate * t : t, final_configuration(sys));
        }
        if (step == plan.steps) break;
        model->advance(sys, run.forces, p.dt, p.rate, step);
        result.force_evaluations += evals_per_step;
    }
    result.force_evaluations += 1;  // the final state's evaluation
    result.correlation_x = correlation.bin_centres();
    result.correlation_g = correlation.g();
    return run.finish();
}

}  // namespace jamsim
