#include "jamsim/dynamics/replica.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "jamsim/dynamics/force_field.hpp"
#include "jamsim/dynamics/sllod.hpp"
#include "jamsim/minimize/minimizer.hpp"
#include "jamsim/observe/velocity_correlation.hpp"

namespace jamsim {

namespace {
template <class T> std::string str(T v) {
    std::ostringstream os;
    os.precision(17);
    os << v;
    return os.str();
}
bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }
} // namespace

std::string to_string(Integrator integrator) {
    return integrator == Integrator::Euler ? "euler" : "heun";
}

Integrator integrator_from_string(const std::string& name) {
    if (name == "euler") return Integrator::Euler;
    if (name == "heun") return Integrator::Heun;
    throw std::invalid_argument("unknown integrator '" + name + "' (known: euler, heun)");
}

std::vector<ParamError> validate(const ReplicaParams& p) {
    std::vector<ParamError> e;
    bool known_model = false;
    std::string names;
    auto all_models = model_names();
    for (const auto& m : static_model_names()) all_models.push_back(m);
    for (const auto& m : all_models) {
        known_model = known_model || m == p.model;
        names += (names.empty() ? "" : ", ") + m;
    }
    const bool static_model = is_static_model(p.model);
    if (!known_model) e.push_back({"model", p.model, "one of: " + names});
    if (p.n < 2) e.push_back({"N", str(p.n), "an integer >= 2"});
    else if (p.size_ratio != 1.0 && p.n % 2 != 0)
        e.push_back({"N", str(p.n), "an even number (50:50 mixture; size_ratio = 1 allows odd N)"});
    if (!(p.phi > 0.0 && p.phi < 1.0)) e.push_back({"phi", str(p.phi), "0 < phi < 1"});
    if (!(std::isfinite(p.rate) && p.rate >= 0.0)) e.push_back({"rate", str(p.rate), "rate >= 0"});
    if ((p.rate > 0.0 || p.model == "QS" || p.model == "SHEARED") && !finite_positive(p.strain))
        e.push_back({"strain", str(p.strain), "strain > 0"});
    if (p.rate == 0.0 && !static_model && !finite_positive(p.time))
        e.push_back({"time", str(p.time), "time > 0 (needed when rate = 0)"});
    if (!(std::isfinite(p.transient) && p.transient >= 0.0))
        e.push_back({"transient", str(p.transient), "transient >= 0"});
    if (!finite_positive(p.sample_interval))
        e.push_back({"sample-interval", str(p.sample_interval), "sample-interval > 0"});
    if (!finite_positive(p.dt)) e.push_back({"dt", str(p.dt), "dt > 0"});
    if (!(std::isfinite(p.alpha) && p.alpha > 1.0))
        e.push_back({"alpha", str(p.alpha), "alpha > 1 (2 harmonic, 2.5 Hertzian)"});
    if (!(std::isfinite(p.size_ratio) && p.size_ratio >= 1.0))
        e.push_back({"size-ratio", str(p.size_ratio), "size-ratio >= 1"});
    if (!finite_positive(p.skin)) e.push_back({"skin", str(p.skin), "skin > 0"});
    if (!finite_positive(p.kd)) e.push_back({"kd", str(p.kd), "kd > 0"});
    if (!finite_positive(p.delta)) e.push_back({"delta", str(p.delta), "delta > 0"});
    if (!finite_positive(p.mass)) e.push_back({"mass", str(p.mass), "mass > 0"});
    const std::pair<const char*, Damping> massive[] = {
        {"RD", Damping::RD}, {"CD", Damping::CD}, {"CDn", Damping::CDn}, {"CDt", Damping::CDt}};
    for (const auto& [name, damping] : massive)
        if (p.model == name && finite_positive(p.dt) && finite_positive(p.mass) &&
            finite_positive(p.kd) && p.dt > sllod_stable_dt(damping, p.mass, p.kd))
            e.push_back({"dt", str(p.dt),
                         "dt <= " + str(sllod_stable_dt(damping, p.mass, p.kd)) + " for " + name +
                             " with mass " + str(p.mass) + " and kd " + str(p.kd) +
                             " (stability of the integrator)"});
    if (const auto known = minimizer_names();
        std::find(known.begin(), known.end(), p.minimizer) == known.end())
        e.push_back({"minimizer", p.minimizer, "cg, cg-pr or fire"});
    if (!finite_positive(p.strain_step)) e.push_back({"strain-step", str(p.strain_step), "strain-step > 0"});
    if (!finite_positive(p.energy_floor))
        e.push_back({"energy-floor", str(p.energy_floor), "energy-floor > 0"});
    if (!(std::isfinite(p.force_tol) && p.force_tol >= 0.0))
        e.push_back({"force-tol", str(p.force_tol), "force-tol >= 0"});
    if (!(std::isfinite(p.force_tol_abs) && p.force_tol_abs >= 0.0))
        e.push_back({"force-tol-abs", str(p.force_tol_abs), "force-tol-abs >= 0"});
    if (p.force_tol == 0.0 && p.force_tol_abs == 0.0)
        e.push_back({"force-tol", "0", "force-tol > 0 or force-tol-abs > 0 (a reachable stopping rule)"});
    if (!finite_positive(p.temperature)) e.push_back({"temperature", str(p.temperature), "temperature > 0"});
    if (!finite_positive(p.cooling_time))
        e.push_back({"cooling-time", str(p.cooling_time), "cooling-time > 0"});
    if (!(std::isfinite(p.phi_tol) && p.phi_tol > 0.0 && p.phi_tol < 1e-2))
        e.push_back({"phi-tol", str(p.phi_tol), "0 < phi-tol < 0.01"});
    if (p.solver != "auto" && p.solver != "petsc" && p.solver != "eigen")
        e.push_back({"solver", p.solver, "auto, petsc or eigen"});
    return e;
}

Schedule schedule_of(const ReplicaParams& p) {
    if (is_static_model(p.model) && p.model != "QS") return {0, 1};  // one state
    if (p.model == "QS")  // steps are minimisations after strain steps
        return {static_cast<std::int64_t>(std::ceil(p.strain / p.strain_step - 1e-9)),
                std::max<std::int64_t>(1, std::llround(p.sample_interval / p.strain_step))};
    const double duration = p.rate > 0.0 ? p.strain / p.rate : p.time;
    const double sample_time = p.rate > 0.0 ? p.sample_interval / p.rate : p.sample_interval;
    const auto steps = static_cast<std::int64_t>(std::ceil(duration / p.dt - 1e-9));
    const auto every = std::max<std::int64_t>(1, std::llround(sample_time / p.dt));
    return {steps, every};
}

FinalConfiguration final_configuration(const System& sys) {
    const Particles& p = sys.particles;
    const std::size_t n = p.size();
    FinalConfiguration out{std::vector<double>(n), std::vector<double>(n), std::vector<double>(n),
                           sys.box.side(), sys.box.strain()};
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

int evaluations_per_step(const ReplicaParams& p) {
    const bool heun_massive = p.model == "CD" || p.model == "CDn" || p.model == "CDt";
    return heun_massive || p.integrator == Integrator::Heun ? 2 : 1;
}

System initial_system(const ReplicaParams& p) {
    return random_system(p.n, p.phi, SizeMix{p.size_ratio}, p.seed, p.replica);
}

ReplicaResult run_replica(const ReplicaParams& p, const std::function<void()>& after_sample) {
    const auto errors = validate(p);
    if (!errors.empty())
        throw std::invalid_argument("replica parameter " + errors.front().key + " = " +
                                    errors.front().value + ": allowed " + errors.front().allowed);
    if (is_static_model(p.model)) return run_static_replica(p, after_sample);
    const auto start = std::chrono::steady_clock::now();
    ReplicaResult result{TimeSeries{}, initial_system(p)};
    System& sys = result.final_state;
    ForceField forces(potential::make_soft_sphere(p.alpha), p.skin);
    auto model = make_model(p.model, ModelParams{p.kd, p.integrator, p.delta, p.petsc_options, p.solver, p.mass});
    const Schedule plan = schedule_of(p);
    const double inv_n = 1.0 / static_cast<double>(p.n);
    VelocityCorrelation correlation(sys.box.side());
    const std::int64_t evals_per_step = evaluations_per_step(p);

    for (std::int64_t step = 0;; ++step) {
        const bool sample_now = step % plan.sample_every == 0;
        // Models that evaluate the new state's forces themselves (RD's splitting) need the
        // driver's evaluation only for the first state and for the tallies of a sample.
        ForceResult f{};
        if (step == 0 || sample_now || !model->leaves_forces_current()) {
            f = forces.compute(sys, sample_now ? Tally::Full : Tally::ForcesOnly);
            if (step > 0 && model->leaves_forces_current()) result.force_evaluations += 1;
        }
        model->prepare(sys, forces, p.rate);
        if (sample_now) {
            const double t = static_cast<double>(step) * p.dt;
            const Dissipation dis = model->dissipation(sys, forces, p.rate);
            const double sigma = f.shear_stress(sys.box);
            const double sigma_total = sigma + dis.shear_stress + dis.shear_stress_kinetic;
            const Sample s{t,
                           p.rate * t,
                           f.energy * inv_n,
                           f.pressure(sys.box),
                           sigma,
                           2.0 * static_cast<double>(f.contacts) * inv_n,
                           model->nonaffine_velocity_sq(sys),
                           dis.pressure,
                           dis.shear_stress,
                           sigma_total * p.rate * sys.box.area() * inv_n,
                           dis.power * inv_n,
                           dis.kinetic_energy * inv_n,
                           dis.pressure_kinetic,
                           dis.shear_stress_kinetic,
                           model->solver_iterations(),
                           p.phi};
            if (!std::isfinite(s.energy_per_particle) || !std::isfinite(s.pressure))
                throw std::runtime_error("non-finite state at t = " + str(t) +
                                         " (time step too large?)");
            result.series.push(s);
            const bool steady = p.rate > 0.0 ? s.strain >= p.transient : s.time >= p.transient;
            if (steady) {
                model->store_velocities(sys);
                correlation.accumulate(sys);
            }
            if (after_sample) after_sample();
        }
        if (step == plan.steps) break;
        model->advance(sys, forces, p.dt, p.rate);
        result.force_evaluations += evals_per_step;
    }
    result.force_evaluations += 1;  // the final state's evaluation
    result.list_builds = static_cast<std::int64_t>(forces.list().builds());
    result.correlation_x = correlation.bin_centres();
    result.correlation_g = correlation.g();
    result.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

} // namespace jamsim
