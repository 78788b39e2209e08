#pragma once
// A campaign's wall time: its chains, its critical path and the farm's scheduler run as a
// discrete-event simulation (campaign/scheduler.hpp) on per-replica seconds, for the dry run
// and `jamsim plan`.
#include <cstdint>
#include <string>
#include <vector>

#include "jamsim/campaign/scheduler.hpp"
#include "jamsim/spec/campaign_spec.hpp"

namespace jamsim {

/// Where and how a campaign runs, for its wall time.
struct WallTimePlan {
    int ranks = 1;             ///< ranks of each task
    int threads = 1;           ///< threads of each rank's replica
    int shards = 1;            ///< Slurm array tasks (chains kept whole: chain % shards)
    double time_limit = 0;     ///< seconds per task (0: none)
    double signal_lead = 300;  ///< seconds of the batch system's warning before the limit
    SpeedupModel speedup;      ///< a replica's speed-up on `threads`
};

/// The replicas as simulate_schedule takes them: the farm's estimated cost, `seconds` (one
/// thread, per replica) and the speed-up of each on `threads`: the model's for its kernel
/// part, none for its `serial` part (its samples).
std::vector<SimulatedReplica> simulated_replicas(const CampaignSpec& spec, const std::vector<double>& seconds,
                                                 const std::vector<double>& serial, int threads,
                                                 const SpeedupModel& model);

/// The farm run on `ranks` × `threads` of the replicas `ids` (whole chains) simulated.
SimulatedRun simulate_part(const CampaignSpec& spec, const std::vector<SimulatedReplica>& replicas,
                           const std::vector<std::int64_t>& ids, int ranks, int threads);

/// "chain 12: replicas 4, 40, ... (N = 65536, phi = 0.8, seed = 1; 9 rates, 1e-4 down to 1e-7)".
std::string describe_chain(const CampaignSpec& spec, const Chains& chains, std::int64_t chain);

/// "42 s", "12.5 min", "3.20 h".
std::string duration(double seconds);

/// The speed-up model in words.
std::string describe_speedup(const SpeedupModel& model);

}  // namespace jamsim
