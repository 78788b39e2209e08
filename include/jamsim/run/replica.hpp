#pragma once
// The run layer: one replica from its parameters to its rows. Above dynamics, minimisation
// and protocols; below io (files, archives) and the campaign farm.
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

#include "jamsim/core/system.hpp"
#include "jamsim/observe/time_series.hpp"
#include "jamsim/observe/velocity_correlation.hpp"
#include "jamsim/params/parameters.hpp"
#include "jamsim/run/model_registry.hpp"

namespace jamsim {

struct ReplicaState;

/// What a finished replica hands back.
struct ReplicaResult {
    TimeSeries series;
    System final_state;
    /// The state at its last checkpoint step (none if it had none): a longer run of the same
    /// replica continues from it bitwise (the campaign keeps it as a final checkpoint).
    std::shared_ptr<const ReplicaState> last_checkpoint = {};
    std::vector<double> correlation_x = {};  ///< bin centres of g_y(x), d_s
    std::vector<double> correlation_g = {};  ///< g_y(x) over the steady state (strain ≥ transient)
    std::int64_t force_evaluations = 0;
    std::int64_t list_builds = 0;
    double wall_seconds = 0.0;
};

/// Everything needed to continue a replica bitwise from a checkpoint step. Kernel caches (the
/// neighbour list, CD0's factor or preconditioner, a minimiser's search direction) are not
/// part of it: at every checkpoint step (every `checkpoint_steps` steps) the run drops them,
/// interrupted or not, so a resumed run and an uninterrupted one continue from the same state.
struct ReplicaState {
    std::int64_t step = 0;                       ///< the step the run continues with (a checkpoint step)
    std::int64_t steps = 0;                      ///< steps of the whole replica (progress = step / steps)
    System system;                               ///< every particle array in memory order, and the box
    TimeSeries series = {};                      ///< the rows so far
    VelocityCorrelation::Sums correlation = {};  ///< g_y sums so far (dynamics)
    /// A minimisation protocol's own state at this step (a φ_J search's bracket; empty else).
    std::vector<double> protocol = {};
    std::int64_t force_evaluations = 0;
    std::int64_t list_builds = 0;
    double wall_seconds = 0.0;  ///< compute time of the replica before this state
};

/// What the caller does at a replica's checkpoint steps (all callbacks optional).
struct CheckpointPolicy {
    std::function<bool()> due;                      ///< save the state now?
    std::function<void(const ReplicaState&)> save;  ///< save it (a file, rows in an archive)
    std::function<bool()> stop;                     ///< stop after this checkpoint step?
};

/// Thrown by a run that stopped at a checkpoint step because CheckpointPolicy::stop asked it
/// to (a signal): its state was saved there; run it again with that state to continue.
struct ReplicaInterrupted : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// The final configuration in output form: sheared coordinates folded into [0, L), ordered
/// by particle tag (creation order), with the box.
struct FinalConfiguration {
    std::vector<double> x, y, diameter;  ///< shape [N], d_s
    double box_side = 0.0;               ///< L
    double box_strain = 0.0;             ///< γ; lab x = x + γ y
};
FinalConfiguration final_configuration(const System& sys);

/// How a replica runs besides its parameters.
struct RunContext {
    SampleHook after_sample = {};  ///< called after every sample
    /// Called with each configuration frame (ReplicaParams::frame_interval > 0): its index k
    /// (step k · frame_every), its strain (time at rate 0) and the configuration. A resumed
    /// run calls it again, with the same bits, for the frames from its checkpoint step on.
    std::function<void(std::int64_t index, double strain, const FinalConfiguration&)> on_frame = {};
    const CheckpointPolicy* checkpoints = nullptr;
    const ReplicaState* resume = nullptr;  ///< continue from this state instead of the start
    /// Start from this configuration instead of random positions (ReplicaParams::initial;
    /// the caller reads it, see io/initial_states.hpp).
    const System* initial = nullptr;
};

/// Random positions keyed by (seed, replica_identity).
System initial_system(const ReplicaParams& params);

/// The configuration a replica starts from when it has no initial one: initial_system,
/// relaxed by its model's start protocol where it has one (CD0: relax_cd0_start).
System start_system(const ReplicaParams& params);

/// Run one replica from its initial configuration (or context.resume) through its
/// registration's run function; throws std::invalid_argument for unusable parameters,
/// std::runtime_error when the state becomes non-finite, ReplicaInterrupted when stopped.
ReplicaResult run_replica(const ReplicaParams& params, const RunContext& context = {});

/// The run function of every dynamical model (ModelInfo::run for ModelKind::Dynamics).
ReplicaResult run_dynamics(const ReplicaParams& params, const RunContext& context);

}  // namespace jamsim
