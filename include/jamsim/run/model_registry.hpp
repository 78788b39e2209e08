#pragma once
// Every model and protocol a replica can run, registered once with what the run layer needs:
// the parameters it reads, its force evaluations per step, its stable time step, its
// schedule and cost estimate, and its run function. Nothing outside this registry compares
// model names.
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "jamsim/parallel/thread_scaling.hpp"
#include "jamsim/dynamics/model.hpp"
#include "jamsim/params/parameters.hpp"

namespace jamsim {

struct ReplicaResult;
struct RunContext;

/// Called after every sample with the fraction of the replica's steps done (NaN where a
/// protocol cannot tell: the minimisations); the campaign farm answers work requests from it
/// and notes the progress. It must not touch the replica.
using SampleHook = std::function<void(double done)>;

/// Steps a replica takes and steps between its samples (both ends are sampled).
struct Schedule {
    std::int64_t steps = 0;
    std::int64_t sample_every = 1;
    std::int64_t frame_every = 0;  ///< steps between configuration frames (0: none)
};

enum class ModelKind : std::uint8_t {
    Dynamics,      ///< integrates equations of motion (RD0, CD0, RD, CD, CDn, CDt, ...)
    Minimisation,  ///< minimises the energy (QS, RAND, COMPRESS, COOL, ...)
};

struct ModelInfo {
    std::string_view name;
    ModelKind kind;
    std::string_view summary;
    /// Parameters read besides the common ones (kCommonParameters).
    std::span<const std::string_view> parameters;
    int (*evaluations_per_step)(const ReplicaParams& p);
    /// Largest stable Δt (+∞: no limit); validate() refuses a larger dt.
    double (*stable_dt)(const ReplicaParams& p);
    Schedule (*schedule)(const ReplicaParams& p);
    /// Estimated particle force evaluations of the whole replica (for ordering and --dry-run).
    double (*cost)(const ReplicaParams& p);
    ReplicaResult (*run)(const ReplicaParams& p, const RunContext& context);
    /// Dynamics: the model (nullptr for minimisation protocols).
    std::unique_ptr<Model> (*make)(const ReplicaParams& p, const RandomKey& key) = nullptr;
    /// The steps checkpoint_steps counts when they are not the schedule's (a protocol's
    /// cooling or quasistatic-shear stage); nullptr: the schedule's steps.
    std::int64_t (*checkpointed_steps)(const ReplicaParams& p) = nullptr;
    /// After those steps comes a φ_J search with a checkpoint step before every minimisation,
    /// so a checkpoint's step has no upper bound.
    bool open_ended = false;
    /// strain (time at rate 0) is a run length: a longer run of the replica continues it, so a
    /// finished replica keeps its last checkpoint and a campaign can be extended.
    bool extendable = false;
    /// Memory a replica needs per disk (bytes), for the memory check before a run.
    double bytes_per_disk = 256.0;
    /// What the stable Δt rests on (DynamicsInfo::stable_dt_basis); nullptr: mass and kd.
    std::string (*stable_dt_basis)(const ReplicaParams& p) = nullptr;
    /// An advisory note for the run log ("" when none; DynamicsInfo::advisory).
    std::string (*advisory)(const ReplicaParams& p) = nullptr;
    /// The start protocol on random positions (DynamicsInfo::relax_start); nullptr: none.
    void (*relax_start)(System& sys, const ReplicaParams& p) = nullptr;
    /// How its kernel gains from threads (DynamicsInfo::thread_scaling; minimiser for the
    /// minimisation protocols).
    ThreadScaling thread_scaling = ThreadScaling::pair_loop;
};

/// Every registered model, in registration order.
std::span<const ModelInfo> models();
/// The registration of `name`, or nullptr.
const ModelInfo* find_model(std::string_view name);
/// The registration of p.model; throws std::invalid_argument listing the known names.
const ModelInfo& model_of(const ReplicaParams& p);
/// "RD0, CD0, ..." for messages.
std::string model_list();

/// Parameters every replica uses: model, N, phi, seed, alpha, size_ratio, skin. The
/// dynamics also use rate, transient, sample_interval and strain (rate > 0) or time (rate 0).
bool uses_parameter(const ReplicaParams& p, std::string_view key);
/// Whether p's run length, transient and samples are times (a dynamics replica at rate 0),
/// not strains.
inline bool runs_in_time(const ReplicaParams& p) { return uses_parameter(p, "time"); }
/// The rows of the parameter table that p's model uses, in table order.
std::vector<const ParamInfo*> used_parameters(const ReplicaParams& p);

/// Every violation among the parameters p's model uses, including its stable Δt (empty when
/// usable). An unknown model is the only error reported then.
std::vector<ParamError> validate(const ReplicaParams& p);
/// Advisory warnings for a valid replica: limits that are not refused but may spoil the
/// result (few samples after the transient; a stable Δt that holds only for the overlaps it
/// assumes). Each is a (kind, text) pair: a run prints each kind once in its log.
std::vector<std::pair<std::string, std::string>> advisories(const ReplicaParams& p);

/// A nominal single-core throughput (particle force evaluations per second; the measured
/// RD0 figure, tests/bench/README.md) for time estimates before anything has been measured.
inline constexpr double kNominalEvaluationsPerSecond = 7e7;
/// The most steps one dynamics replica may take (validate() refuses more): far below 2^63,
/// and far beyond what any allocation can run.
inline constexpr double kMostSteps = 1e15;

Schedule schedule_of(const ReplicaParams& p);
/// The steps `checkpoint_steps` counts (ModelInfo::checkpointed_steps, else the schedule's).
std::int64_t checkpointed_steps(const ReplicaParams& p);
double estimated_cost(const ReplicaParams& p);
int evaluations_per_step(const ReplicaParams& p);
/// Memory one running replica needs (bytes, without the libraries' base): its disks, its
/// rows (held in memory, copied at checkpoints) and the neighbour list's cell grid (which
/// dominates in a dilute box).
double estimated_memory(const ReplicaParams& p);
/// Samples (rows) a replica writes.
std::int64_t sample_count(const ReplicaParams& p);
/// Configuration frames the replica writes (0 without frame_interval).
std::int64_t frame_count(const ReplicaParams& p);

/// "key=value key=value ..." of the parameters p's model uses (17 significant digits where
/// needed): the canonical description of a replica (fingerprints, messages).
std::string describe(const ReplicaParams& p);
/// The same without the run length (strain, or time at rate 0) of an extendable model: what a
/// checkpoint must match to continue a replica that has been extended.
std::string describe_without_run_length(const ReplicaParams& p);
/// The replica's random identity: a 64-bit hash of its model and of the physical parameters
/// it uses (Identity::Physics), seed excluded. With the seed it keys every random number,
/// so a replica is the same in any campaign that contains it and whatever its position in
/// the sweep, run length, time step or numerical settings.
std::uint64_t replica_identity(const ReplicaParams& p);
/// (seed, replica_identity): the key of every random number of the replica.
RandomKey random_key(const ReplicaParams& p);

}  // namespace jamsim
