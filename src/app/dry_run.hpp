#pragma once
// `jamsim run --dry-run`: every replica with its estimated cost, calibrated on this machine,
// and the wall time of the planned run.
#include <string>

#include "jamsim/io/campaign_spec.hpp"

namespace jamsim::app {

/// What --dry-run estimates for.
struct DryRunPlan {
    bool calibrate = true;
    int ranks = 1;           ///< ranks of the planned run
    int shards = 1;          ///< Slurm array tasks
    double time_limit = 0;   ///< seconds per task (0: none)
};

/// The dry run's table and totals on stdout.
void print_dry_run(const CampaignSpec& spec, const std::string& output, const DryRunPlan& plan);

} // namespace jamsim::app
