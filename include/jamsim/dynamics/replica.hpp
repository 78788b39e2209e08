#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "jamsim/core/system.hpp"
#include "jamsim/dynamics/model.hpp"
#include "jamsim/observe/time_series.hpp"

namespace jamsim {

/// Everything that defines one replica; its output depends on nothing else.
struct ReplicaParams {
    std::string model = "RD0";
    std::int64_t n = 1024;          ///< number of disks N
    double phi = 0.84;              ///< packing fraction φ = Σ π d_i² / (4 L²)
    double rate = 1e-4;             ///< shear rate γ̇, 1/τ
    double strain = 2.0;            ///< total strain to run (used when rate > 0)
    double time = 0.0;              ///< total time to run, τ (used when rate == 0)
    double transient = 0.0;         ///< strain (or time at rate 0) excluded from averages
    /// Strain between samples (time when rate == 0). Samples fall on whole steps: the
    /// spacing used is round(interval / (rate·dt)) steps (at least 1), and the stored
    /// `strain`/`time` columns give the exact values.
    double sample_interval = 0.01;
    double dt = 0.2;                ///< time step Δt, τ
    double alpha = 2.0;             ///< potential exponent α (2 harmonic, 2.5 Hertzian)
    double size_ratio = 1.4;        ///< large/small diameter (1 = monodisperse)
    double skin = 0.3;              ///< neighbour-list skin, d_s
    double kd = 1.0;                ///< dissipation coefficient k_d
    double delta = 1e-3;            ///< CD0 substrate drag δ = k_0/k_d (on u, see Cd0)
    std::string petsc_options;      ///< CD0 solver options, e.g. "-cd0_pc_type icc"
    std::string solver = "auto";    ///< CD0 backend: "auto" (by N), "petsc" or "eigen"
    double mass = 1.0;              ///< massive models (RD, CD, CDn, CDt): small-disk mass
    Integrator integrator = Integrator::Euler;
    // Minimisation (models QS, RAND, COMPRESS; see jamsim/minimize/minimizer.hpp).
    std::string minimizer = "cg";   ///< "cg" (hybrid HS/DY), "cg-pr" (Polak–Ribière) or "fire" (FIRE 2.0)
    double strain_step = 1e-4;      ///< QS: Δγ between minimisations
    double energy_floor = 1e-16;    ///< E/N below this after minimisation: unjammed, k_e
    double force_tol = 1e-10;       ///< force balance relative to the mean contact force
    double force_tol_abs = 1e-14;   ///< force balance floor, k_e/d_s
    double phi_tol = 1e-6;          ///< COMPRESS: width of the final φ_J bracket
    double temperature = 1e-3;      ///< COOL: starting temperature T₀, k_e
    double cooling_time = 1e4;      ///< COOL: time over which T falls linearly to 0, τ
    std::uint64_t seed = 1;
    std::uint32_t replica = 0;      ///< replica id within a campaign (part of the RNG key)
};

/// Models that minimise instead of integrating (thesis §4.7, Papers I–III):
///   QS:       quasistatic shear: γ → γ + strain_step (affine), minimise; one sample per
///             sample_interval of strain
///   RAND:     random positions at φ (an infinite-temperature quench), minimised: one sample
///   COMPRESS: RAND, then compression/decompression to the configuration's own φ_J: one
///             sample of the jammed state at φ_J⁺ (its packing_fraction is φ_J)
///   SHEARED:  the sheared ensemble: QS shear at φ to `strain`, then the compression/
///             decompression search for that configuration's φ_J (at its strain): one sample
///   COOL:     thermal preparation: overdamped Langevin dynamics (RD0 with noise) at
///             T(t) = T₀ (1 − t/cooling_time), i.e. cooling at the rate T₀/cooling_time, then a
///             quench by minimisation: one sample
///   COOL_COMPRESS: the same cooling, then the compression/decompression search for the
///             cooled configuration's φ_J (Paper I): one sample, as COMPRESS
bool is_static_model(const std::string& model);
const std::vector<std::string>& static_model_names();

/// A problem with one parameter, phrased for a person.
struct ParamError {
    std::string key;      ///< parameter name as the user writes it
    std::string value;    ///< the offending value
    std::string allowed;  ///< what is allowed
};

/// All violations (empty when the parameters are usable).
std::vector<ParamError> validate(const ReplicaParams& params);

/// Number of steps and steps between samples implied by the parameters.
struct Schedule {
    std::int64_t steps;
    std::int64_t sample_every;
};
Schedule schedule_of(const ReplicaParams& params);

/// Force evaluations per step: 2 for Heun and for the massive models (always Heun), else 1.
int evaluations_per_step(const ReplicaParams& params);

std::string to_string(Integrator integrator);
Integrator integrator_from_string(const std::string& name);  ///< throws std::invalid_argument

/// What a finished replica hands back.
struct ReplicaResult {
    TimeSeries series;
    System final_state;
    std::vector<double> correlation_x = {};  ///< bin centres of g_y(x), d_s
    std::vector<double> correlation_g = {};  ///< g_y(x) over the steady state (strain ≥ transient)
    std::int64_t force_evaluations = 0;
    std::int64_t list_builds = 0;
    double wall_seconds = 0.0;
};

/// The final configuration in output form: sheared coordinates folded into [0, L), ordered
/// by particle tag (creation order), with the box.
struct FinalConfiguration {
    std::vector<double> x, y, diameter;  ///< shape [N], d_s
    double box_side = 0.0;               ///< L
    double box_strain = 0.0;             ///< γ; lab x = x + γ y
};
FinalConfiguration final_configuration(const System& sys);

/// The initial configuration of a replica (random positions keyed by seed and replica id).
System initial_system(const ReplicaParams& params);

/// Run one replica from its initial configuration; throws std::runtime_error when the state
/// becomes non-finite.
/// `after_sample`, if given, is called after every sample (the campaign farm uses it to
/// answer work requests while rank 0 computes); it must not touch the replica.
/// The minimisation models (is_static_model): same result layout as the dynamics.
ReplicaResult run_static_replica(const ReplicaParams& params,
                                 const std::function<void()>& after_sample = {});

ReplicaResult run_replica(const ReplicaParams& params,
                          const std::function<void()>& after_sample = {});

} // namespace jamsim
