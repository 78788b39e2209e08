// The minimisation models of a campaign: QS shear, the RAND and COOL quenches and the
// compression to φ_J (COMPRESS, COOL_COMPRESS, SHEARED). Each produces rows of the same TimeSeries as the dynamics, with the static columns
// (packing_fraction, contact_number_nonrattler, rattler_fraction, excess_contacts, jammed,
// max_force) filled in and solver_iterations holding the minimiser's iterations.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "jamsim/core/rng.hpp"
#include "jamsim/dynamics/force_field.hpp"
#include "jamsim/dynamics/replica.hpp"
#include "jamsim/minimize/minimizer.hpp"
#include "jamsim/protocols/jamming.hpp"
#include "jamsim/protocols/preparation.hpp"

namespace jamsim {

bool is_static_model(const std::string& model) {
    const auto& names = static_model_names();
    return std::find(names.begin(), names.end(), model) != names.end();
}

const std::vector<std::string>& static_model_names() {
    static const std::vector<std::string> names{"QS", "RAND", "COMPRESS", "COOL", "COOL_COMPRESS", "SHEARED"};
    return names;
}

namespace {

MinimizeCriteria criteria_of(const ReplicaParams& p) {
    MinimizeCriteria c;
    c.energy_floor = p.energy_floor;
    c.force_tol = p.force_tol;
    c.force_tol_abs = p.force_tol_abs;
    return c;
}

Sample sample_of(const StaticState& st, const System& sys, double step, double strain) {
    const double n = static_cast<double>(sys.particles.size());
    Sample s{step,
             strain,
             st.minimum.energy_per_particle,
             st.minimum.pressure,
             st.minimum.shear_stress,
             2.0 * static_cast<double>(st.minimum.contacts) / n,
             0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
             static_cast<double>(st.minimum.iterations)};
    s.packing_fraction = st.phi;
    // Contacts of an unjammed state (E/N below the floor) are round-off, not a network.
    s.contact_number_nonrattler = st.jammed() ? st.network.z() : Sample::kNone;
    s.rattler_fraction = st.jammed() ? st.network.rattler_fraction() : Sample::kNone;
    s.excess_contacts = st.jammed() ? static_cast<double>(st.network.excess_contacts()) : Sample::kNone;
    s.jammed = st.jammed() ? 1.0 : 0.0;
    s.max_force = st.minimum.max_force;
    return s;
}

} // namespace

ReplicaResult run_static_replica(const ReplicaParams& p, const std::function<void()>& after_sample) {
    const auto start = std::chrono::steady_clock::now();
    ReplicaResult result{TimeSeries{}, initial_system(p)};
    System& sys = result.final_state;
    ForceField forces(potential::make_soft_sphere(p.alpha), p.skin);
    auto minimizer = make_minimizer(p.minimizer);
    const MinimizeCriteria c = criteria_of(p);
    auto record = [&](const StaticState& st, double step, double strain) {
        result.series.push(sample_of(st, sys, step, strain));
        if (after_sample) after_sample();
    };
    std::int64_t evaluations = 0;
    auto minimise = [&] {  // quench the configuration as it is, counting its cost
        StaticState st = quench(sys, forces, *minimizer, c);
        evaluations += st.minimum.force_evaluations;
        return st;
    };
    if (p.model == "QS") {  // γ → γ + Δγ through the Lees–Edwards box (affine), then minimise
        const auto [steps, every] = schedule_of(p);
        double strain = 0.0;
        for (std::int64_t step = 0;; ++step) {
            const StaticState st = minimise();
            if (step % every == 0) record(st, static_cast<double>(step), strain);
            if (step == steps) break;
            strain = static_cast<double>(step + 1) * p.strain_step;
            apply_strain(sys, forces, sys.box.strain() + p.strain_step);
        }
    } else {
        // The preparation (Paper I), then a quench of the prepared state or its φ_J search.
        if (p.model == "COOL" || p.model == "COOL_COMPRESS")
            evaluations += cool(sys, forces, {p.temperature, p.cooling_time, p.dt, p.kd},
                                RngStream(p.seed, p.replica, RngPurpose::ThermalNoise));
        if (p.model == "SHEARED")  // the sheared ensemble: QS shear to `strain` at φ first
            evaluations += shear_quasistatically(sys, forces, *minimizer, c, p.strain, p.strain_step);
        if (p.model == "RAND" || p.model == "COOL") {
            record(minimise(), 0.0, 0.0);
        } else {  // COMPRESS, COOL_COMPRESS, SHEARED: compression/decompression to φ_J
            const JammingPoint jp = find_jamming_point(sys, forces, *minimizer, c, 1e-3, p.phi_tol);
            evaluations += jp.force_evaluations;
            record(jp.state, 0.0, 0.0);
        }
    }
    result.force_evaluations = evaluations;
    result.list_builds = static_cast<std::int64_t>(forces.list().builds());
    result.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

} // namespace jamsim
