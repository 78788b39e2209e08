#pragma once
// A campaign's wall time printed (campaign/wall_time.hpp computes it), for the dry run and
// `jamsim plan`.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "jamsim/campaign/wall_time.hpp"
#include "jamsim/spec/campaign_spec.hpp"

namespace jamsim::app {

/// "1 replica", "2 replicas": a count with its noun (plural with an s).
inline std::string counted(long long n, const std::string& noun) {
    return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

/// On stdout: the critical path, the most cores usable at once, the makespan bound, the
/// simulated makespan on plan.ranks × plan.threads, and per shard its work, makespan and the
/// requeues it needs under plan.time_limit (with the warning JAMSIM_SIGNAL_LEAD s before).
void print_wall_time(const CampaignSpec& spec, const std::vector<double>& seconds, const std::vector<double>& serial,
                     const WallTimePlan& plan);

/// `--serial-fraction F` (0 <= F <= 1) on `command`, into `fraction`: the speed-up model's one
/// serial fraction for every N instead of its table.
void add_serial_fraction_option(CLI::App& command, double& fraction);

/// `--probe-seconds S` (0 <= S <= 1e6) on `command`, into `seconds`: the cost calibration's
/// probe budget.
void add_probe_seconds_option(CLI::App& command, double& seconds);

}  // namespace jamsim::app
