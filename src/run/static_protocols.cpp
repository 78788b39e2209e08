// The minimisation protocols of a campaign: QS shear, the RAND and COOL quenches and the
// compression to φ_J (COMPRESS, COOL_COMPRESS, SHEARED). Each produces rows of the same
// TimeSeries as the dynamics, with the static columns (packing_fraction,
// contact_number_nonrattler, rattler_fraction, excess_contacts, jammed, max_force) filled in
// and solver_iterations holding the minimiser's iterations. `time` is NaN: a quasistatic
// state has no time; QS rows carry their strain.
#include <limits>
#include <algorithm>
#include <cmath>
#include <optional>

#include "jamsim/core/rng.hpp"
#include "jamsim/dynamics/overdamped_stability.hpp"
#include "jamsim/minimize/minimizer.hpp"
#include "jamsim/protocols/jamming.hpp"
#include "jamsim/protocols/preparation.hpp"
#include "jamsim/run/replica.hpp"
#include "replica_run.hpp"

namespace jamsim {

namespace {

MinimizeCriteria criteria_of(const ReplicaParams& p) {
    MinimizeCriteria c;
    c.energy_floor = p.energy_floor;
    c.force_tol = p.force_tol;
    c.force_tol_abs = p.force_tol_abs;
    return c;
}

Sample sample_of(const StaticState& st, const System& sys, double strain) {
    const double n = static_cast<double>(sys.particles.size());
    const bool jammed = st.jammed();  // an unjammed state's contacts are round-off, not a network
    return {.time = Sample::kNone,
            .strain = strain,
            .energy_per_particle = st.minimum.energy_per_particle,
            .pressure = st.minimum.pressure,
            .shear_stress = st.minimum.shear_stress,
            .contact_number = 2.0 * static_cast<double>(st.minimum.contacts) / n,
            .nonaffine_velocity_sq = 0.0,
            .pressure_dissipative = 0.0,
            .shear_stress_dissipative = 0.0,
            .input_power = 0.0,
            .dissipated_power = 0.0,
            .kinetic_energy_per_particle = 0.0,
            .pressure_kinetic = 0.0,
            .shear_stress_kinetic = 0.0,
            .solver_iterations = static_cast<double>(st.minimum.iterations),
            .packing_fraction = st.phi,
            .contact_number_nonrattler = jammed ? st.network.z() : Sample::kNone,
            .rattler_fraction = jammed ? st.network.rattler_fraction() : Sample::kNone,
            .excess_contacts = jammed ? static_cast<double>(st.network.excess_contacts()) : Sample::kNone,
            .jammed = jammed ? 1.0 : 0.0,
            .max_force = st.minimum.max_force};
}

/// A protocol in progress: the shared run state plus the minimiser and its criteria.
///
/// Checkpoint steps. A protocol counts its steps through its stages: the preparation's
/// steps first (cooling steps of COOL, strain steps of SHEARED's quasistatic shear; 0 for
/// COMPRESS), with a checkpoint step at every multiple of checkpoint_steps, then the φ_J
/// search, whose minimisation m (m ≥ 2) is step `stage + m - 1` and always a checkpoint
/// step (a minimisation costs ~1e3 force evaluations per disk). The final quench of RAND and
/// COOL is a single minimisation, not divided.
struct Protocol : ReplicaRun {
    Protocol(const ReplicaParams& p, const RunContext& context, std::int64_t stage_steps = 0)
        : ReplicaRun(p, context), params(p), after_sample(context.after_sample), minimizer(make_minimizer(p.minimizer)),
          criteria(criteria_of(p)), stage(stage_steps) {
        // A campaign's farm answers its ranks from inside a long minimisation too (rank 0 ran
        // a RAND quench of N = 4096 while the others waited for their next replica).
        if (after_sample)
            criteria.between_iterations = [this] { after_sample(std::numeric_limits<double>::quiet_NaN()); };
    }

    StaticState minimise() {  // quench the configuration as it is, counting its cost
        StaticState st = quench(system(), forces, *minimizer, criteria);
        result.force_evaluations += st.minimum.force_evaluations;
        return st;
    }
    void record(const StaticState& st, double strain) {
        result.series.push(sample_of(st, system(), strain));
        if (after_sample) after_sample(std::numeric_limits<double>::quiet_NaN());
    }
    /// Where a preparation stage resumes: its first step, or `stage` when the run resumes
    /// later (in the φ_J search), which skips the stage.
    std::int64_t stage_start() const { return std::min(first_step(), stage); }
    /// Called before step `step` of the preparation stage. (The minimiser stays: it keeps
    /// nothing from one minimisation to the next, and the stage holds a reference to it.)
    void before_stage_step(std::int64_t step, std::int64_t before_stage, std::int64_t evaluations) {
        result.force_evaluations = before_stage + evaluations;
        if (after_sample && step % MinimizeCriteria::kIterationsBetweenCalls == 0)
            after_sample(std::numeric_limits<double>::quiet_NaN());  // the farm's messages, as above
        checkpoint_step(step, stage + 1);
    }
    void cool_down() {  // overdamped Langevin cooling (Paper I)
        const ReplicaParams& p = params;
        const std::int64_t first = stage_start();
        if (first == stage) return;
        const std::int64_t before_stage = result.force_evaluations;
        result.force_evaluations =
            before_stage + cool(system(), forces, {p.temperature, p.cooling_time, p.dt, p.kd},
                                RngStream(random_key(p), RngPurpose::ThermalNoise), first,
                                [&](std::int64_t step, std::int64_t n) { before_stage_step(step, before_stage, n); });
    }
    void shear() {  // quasistatic shear at phi (the sheared ensemble)
        const std::int64_t first = stage_start();
        if (first == stage) return;
        const std::int64_t before_stage = result.force_evaluations;
        result.force_evaluations =
            before_stage +
            shear_quasistatically(system(), forces, *minimizer, criteria, params.strain, params.strain_step, first,
                                  [&](std::int64_t step, std::int64_t n) { before_stage_step(step, before_stage, n); });
    }
    /// Compression/decompression to φ_J (O'Hern et al.), recorded at `strain` (SHEARED: the
    /// strain its quasistatic shear accumulated).
    void record_jamming_point(double strain = 0.0) {
        std::optional<JammingSearch> resume;
        if (resumed() && first_step() > stage) resume = JammingSearch::unpack(resumed()->protocol);
        // The evaluations before the search; the search counts its own (saved with it).
        const std::int64_t before_search = result.force_evaluations - (resume ? resume->force_evaluations : 0);
        const JammingPoint jp =
            find_jamming_point(system(), forces, *minimizer, criteria, 1e-3, params.phi_tol,
                               resume ? &*resume : nullptr, [&](const JammingSearch& s) {
                                   result.force_evaluations = before_search + s.force_evaluations;
                                   const std::int64_t step = stage + s.minimizations;  // before minimisation m + 1
                                   // Progress: the search takes ~30 minimisations (Δφ from 1e-3 down to phi_tol).
                                   checkpoint(step, stage + std::max(s.minimizations + 1, 30), nullptr, s.pack());
                               });
        result.force_evaluations = before_search + jp.force_evaluations;
        record(jp.state, strain);
    }

    const ReplicaParams& params;
    const SampleHook& after_sample;
    std::unique_ptr<Minimizer> minimizer;
    MinimizeCriteria criteria;
    std::int64_t stage;  ///< steps of the preparation stage
};

ReplicaResult run_qs(const ReplicaParams& p, const RunContext& context) {
    Protocol run(p, context);
    const Schedule plan = schedule_of(p);
    const std::int64_t steps = plan.steps, every = plan.sample_every;
    for (std::int64_t step = run.first_step();; ++step) {  // minimise, then γ → γ + Δγ (affine)
        if (run.checkpoint_step(step, steps)) run.minimizer = make_minimizer(p.minimizer);
        const double strain = static_cast<double>(step) * p.strain_step;
        const StaticState st = run.minimise();
        if (step % every == 0) run.record(st, strain);
        if (step == steps) break;
        apply_strain(run.system(), run.forces, run.system().box.strain() + p.strain_step);
    }
    return run.finish();
}

ReplicaResult run_rand(const ReplicaParams& p, const RunContext& context) {
    Protocol run(p, context);
    run.record(run.minimise(), 0.0);
    return run.finish();
}

ReplicaResult run_compress(const ReplicaParams& p, const RunContext& context) {
    Protocol run(p, context);
    run.record_jamming_point();
    return run.finish();
}

std::int64_t cooling_steps_of(const ReplicaParams& p) {
    return cooling_steps({p.temperature, p.cooling_time, p.dt, p.kd});
}
std::int64_t shear_steps_of(const ReplicaParams& p) { return shear_steps(p.strain, p.strain_step); }

ReplicaResult run_cool(const ReplicaParams& p, const RunContext& context) {
    Protocol run(p, context, cooling_steps_of(p));
    run.cool_down();
    run.record(run.minimise(), 0.0);
    return run.finish();
}

ReplicaResult run_cool_compress(const ReplicaParams& p, const RunContext& context) {
    Protocol run(p, context, cooling_steps_of(p));
    run.cool_down();
    run.record_jamming_point();
    return run.finish();
}

ReplicaResult run_sheared(const ReplicaParams& p, const RunContext& context) {
    Protocol run(p, context, shear_steps_of(p));
    run.shear();
    run.record_jamming_point(static_cast<double>(shear_steps_of(p)) * p.strain_step);
    return run.finish();
}

Schedule one_state(const ReplicaParams&) { return {.steps = 0, .sample_every = 1}; }
int one_evaluation(const ReplicaParams&) { return 1; }

// Parameters: the minimiser and its stopping rule, plus what each protocol adds.
constexpr std::string_view kQs[] = {"minimizer",   "energy_floor", "force_tol",       "force_tol_abs",   "strain",
                                    "strain_step", "transient",    "sample_interval", "checkpoint_steps"};
constexpr std::string_view kRand[] = {"minimizer", "energy_floor", "force_tol", "force_tol_abs"};
constexpr std::string_view kCompress[] = {"minimizer", "energy_floor", "force_tol", "force_tol_abs", "phi_tol"};
constexpr std::string_view kCool[] = {"minimizer",    "energy_floor", "force_tol", "force_tol_abs",   "temperature",
                                      "cooling_time", "dt",           "kd",        "checkpoint_steps"};
constexpr std::string_view kCoolCompress[] = {"minimizer", "energy_floor",    "force_tol",    "force_tol_abs",
                                              "phi_tol",   "temperature",     "cooling_time", "dt",
                                              "kd",        "checkpoint_steps"};
constexpr std::string_view kSheared[] = {"minimizer", "energy_floor", "force_tol", "force_tol_abs",
                                         "strain",    "strain_step",  "phi_tol",   "checkpoint_steps"};

// Cost estimates in force evaluations per disk: a RAND quench ~1e3, a φ_J search ~2e4, a
// QS step ~1e2, a cooling step 1.
double n_of(const ReplicaParams& p) { return static_cast<double>(p.n); }
double qs_steps(const ReplicaParams& p) { return p.strain / p.strain_step; }
std::string cooling_advisory(const ReplicaParams& p) { return overdamped_dt_advisory(p, reservoir_drag_stable_dt); }

}  // namespace

ModelInfo qs_protocol() {
    return {.name = "QS",
            .kind = ModelKind::Minimisation,
            .summary = "quasistatic shear: strain_step (affine), minimise; a sample per sample_interval",
            .parameters = kQs,
            .evaluations_per_step = one_evaluation,
            .stable_dt = no_dt_limit,
            .schedule =
                [](const ReplicaParams& p) {
                    return Schedule{.steps = static_cast<std::int64_t>(std::ceil(qs_steps(p) - 1e-9)),
                                    .sample_every =
                                        std::max<std::int64_t>(1, std::llround(p.sample_interval / p.strain_step))};
                },
            .cost = [](const ReplicaParams& p) { return n_of(p) * 1e2 * qs_steps(p); },
            .run = run_qs,
            .extendable = true,
            .thread_scaling = ThreadScaling::minimiser};
}

ModelInfo rand_protocol() {
    return {.name = "RAND",
            .kind = ModelKind::Minimisation,
            .summary = "random positions at phi (an infinite-temperature quench), minimised: one state",
            .parameters = kRand,
            .evaluations_per_step = one_evaluation,
            .stable_dt = no_dt_limit,
            .schedule = one_state,
            .cost = [](const ReplicaParams& p) { return n_of(p) * 1e3; },
            .run = run_rand,
            .thread_scaling = ThreadScaling::minimiser};
}

ModelInfo compress_protocol() {
    return {.name = "COMPRESS",
            .kind = ModelKind::Minimisation,
            .summary = "RAND, then compression/decompression to its own phi_J: the jammed state at phi_J+",
            .parameters = kCompress,
            .evaluations_per_step = one_evaluation,
            .stable_dt = no_dt_limit,
            .schedule = one_state,
            .cost = [](const ReplicaParams& p) { return n_of(p) * 2e4; },
            .run = run_compress,
            .open_ended = true,
            .thread_scaling = ThreadScaling::minimiser};
}

ModelInfo cool_protocol() {
    return {.name = "COOL",
            .kind = ModelKind::Minimisation,
            .summary = "overdamped Langevin cooling T(t) = T_0 (1 - t/cooling_time), then a quench",
            .parameters = kCool,
            .evaluations_per_step = one_evaluation,
            .stable_dt = reservoir_drag_stable_dt,  // the cooling is RD0T's Euler step
            .schedule = one_state,
            .cost = [](const ReplicaParams& p) { return n_of(p) * (1e3 + p.cooling_time / p.dt); },
            .run = run_cool,
            .checkpointed_steps = cooling_steps_of,
            .stable_dt_basis = reservoir_drag_dt_basis,
            .advisory = cooling_advisory,
            .thread_scaling = ThreadScaling::minimiser};
}

ModelInfo cool_compress_protocol() {
    return {.name = "COOL_COMPRESS",
            .kind = ModelKind::Minimisation,
            .summary = "COOL's cooling, then the phi_J search of COMPRESS (Paper I)",
            .parameters = kCoolCompress,
            .evaluations_per_step = one_evaluation,
            .stable_dt = reservoir_drag_stable_dt,
            .schedule = one_state,
            .cost = [](const ReplicaParams& p) { return n_of(p) * (2e4 + p.cooling_time / p.dt); },
            .run = run_cool_compress,
            .checkpointed_steps = cooling_steps_of,
            .open_ended = true,
            .stable_dt_basis = reservoir_drag_dt_basis,
            .advisory = cooling_advisory,
            .thread_scaling = ThreadScaling::minimiser};
}

ModelInfo sheared_protocol() {
    return {.name = "SHEARED",
            .kind = ModelKind::Minimisation,
            .summary = "the sheared ensemble: QS shear at phi to strain, then the phi_J search",
            .parameters = kSheared,
            .evaluations_per_step = one_evaluation,
            .stable_dt = no_dt_limit,
            .schedule = one_state,
            .cost = [](const ReplicaParams& p) { return n_of(p) * (2e4 + 1e2 * qs_steps(p)); },
            .run = run_sheared,
            .checkpointed_steps = shear_steps_of,
            .open_ended = true,
            .thread_scaling = ThreadScaling::minimiser};
}

}  // namespace jamsim
