#pragma once
// `jamsim run --dry-run`: every replica with its estimated cost, calibrated on this machine,
// and the wall time of the planned run (critical path, makespan bound, the farm's schedule
// simulated, Slurm shards and their requeues: wall_time.hpp).
#include <string>
#include <vector>

#include "jamsim/campaign/costs.hpp"
#include "jamsim/spec/campaign_spec.hpp"

namespace jamsim::app {

/// slurm/submit_campaign.sh's default warning lead, seconds.
inline constexpr double kDefaultSignalLead = 300;

/// What --dry-run estimates for.
struct DryRunPlan {
    bool calibrate = true;
    int ranks = 1;                                ///< ranks of the planned run
    int shards = 1;                               ///< Slurm array tasks
    double time_limit = 0;                        ///< seconds per task (0: none)
    double signal_lead = kDefaultSignalLead;      ///< seconds of Slurm's warning before it (JAMSIM_SIGNAL_LEAD)
    double serial_fraction = -1;                  ///< the speed-up model's (campaign/scheduler.hpp; < 0: its table)
    bool summary = false;                         ///< one line per (model, N) instead of one per replica (--summary)
    double probe_seconds = kDefaultProbeSeconds;  ///< the calibration's probe budget (--probe-seconds)
};

/// The seconds by which Slurm's warning (SIGUSR1) precedes a task's time limit: the variable
/// JAMSIM_SIGNAL_LEAD that slurm/submit_campaign.sh passes to `sbatch --signal`, 300 unset.
/// Throws CLI::ValidationError unless it is a positive whole number, as the script demands.
double signal_lead_from_environment();

/// The dry run's table and totals on stdout.
void print_dry_run(const CampaignSpec& spec, const std::string& output, const DryRunPlan& plan);

}  // namespace jamsim::app
