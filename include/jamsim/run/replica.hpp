#pragma once
// The run layer: one replica from its parameters to its rows. Above dynamics, minimisation
// and protocols; below io (files, archives) and the campaign farm.
#include <cstdint>
#include <vector>

#include "jamsim/core/system.hpp"
#include "jamsim/observe/time_series.hpp"
#include "jamsim/params/parameters.hpp"
#include "jamsim/run/model_registry.hpp"

namespace jamsim {

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

/// The initial configuration of a replica: random positions keyed by (seed, replica_identity).
System initial_system(const ReplicaParams& params);

/// Run one replica from its initial configuration through its registration's run function;
/// throws std::invalid_argument for unusable parameters and std::runtime_error when the
/// state becomes non-finite. `after_sample`, if given, is called after every sample.
ReplicaResult run_replica(const ReplicaParams& params, const SampleHook& after_sample = {});

/// The run function of every dynamical model (ModelInfo::run for ModelKind::Dynamics).
ReplicaResult run_dynamics(const ReplicaParams& params, const SampleHook& after_sample);

} // namespace jamsim
