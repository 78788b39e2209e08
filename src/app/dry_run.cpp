// `jamsim run --dry-run` (dry_run.hpp).
#include "dry_run.hpp"
#include "wall_time.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <vector>
#include <map>
#include <queue>
#include <tuple>

#include <CLI/CLI.hpp>

#include "jamsim/archive/archive.hpp"
#include "jamsim/archive/archive_file_check.hpp"
#include "jamsim/archive/capacity.hpp"
#include "jamsim/parallel/threads.hpp"
#include "jamsim/run/model_registry.hpp"
#include "jamsim/run/replica.hpp"

namespace jamsim::app {

namespace {

/// --summary: one line per (model, N), the heaviest work first: its replicas, their
/// one-thread core-hours and share of the campaign's, its longest replica, and its share of
/// the archive (time series, g_y, final configurations, frames: ArchiveLayout's rows, which
/// every replica fills to the campaign's longest) with the part in configurations.
void print_groups(const CampaignSpec& spec, const std::vector<double>& seconds) {
    struct Group {
        std::int64_t replicas = 0;
        double seconds = 0, longest = 0, bytes = 0, configuration_bytes = 0;
    };
    const ArchiveLayout layout = archive_layout(spec);
    std::map<std::pair<std::string, std::int64_t>, Group> groups;
    double total_seconds = 0, total_bytes = 0;
    for (std::size_t r = 0; r < spec.replicas.size(); ++r) {
        const ReplicaParams& p = spec.replicas[r];
        Group& g = groups[{p.model, p.n}];
        const double bytes = layout.replica_bytes(p.n);
        ++g.replicas;
        g.seconds += seconds[r];
        g.longest = std::max(g.longest, seconds[r]);
        g.bytes += bytes;
        g.configuration_bytes += layout.configuration_bytes(p.n);
        total_seconds += seconds[r];
        total_bytes += bytes;
    }
    std::vector<std::pair<std::pair<std::string, std::int64_t>, Group>> order(groups.begin(), groups.end());
    std::stable_sort(order.begin(), order.end(),
                     [](const auto& a, const auto& b) { return a.second.seconds > b.second.seconds; });
    std::printf("%-6s %8s %9s %11s %6s %12s %10s %6s %15s\n", "model", "N", "replicas", "core-hours", "work", "longest",
                "archive", "share", "configurations");
    for (const auto& [key, g] : order)
        std::printf("%-6s %8lld %9lld %11.4g %5.1f%% %12s %10s %5.1f%% %14.0f%%\n", key.first.c_str(),
                    static_cast<long long>(key.second), static_cast<long long>(g.replicas), g.seconds / 3600.0,
                    100.0 * g.seconds / std::max(1e-300, total_seconds), duration(g.longest).c_str(),
                    show_bytes(g.bytes).c_str(), 100.0 * g.bytes / std::max(1e-300, total_bytes),
                    100.0 * g.configuration_bytes / std::max(1e-300, g.bytes));
    std::printf("%zu groups (model, N); configurations: the share of a group's archive bytes in final "
                "configurations and frames\n",
                order.size());
}

/// The groups whose throughput is extrapolated: the heaviest ten, then the rest in one line.
void print_extrapolated(const std::vector<ExtrapolatedGroup>& groups, double total_seconds) {
    if (groups.empty()) return;
    double seconds = 0;
    for (const ExtrapolatedGroup& g : groups) seconds += g.seconds;
    std::printf("extrapolated: %zu groups (model, N, phi) not measured hold %.1f%% of the estimated work:\n",
                groups.size(), 100.0 * seconds / std::max(1e-300, total_seconds));
    constexpr std::size_t kShown = 10;
    for (std::size_t k = 0; k < groups.size() && k < kShown; ++k) {
        const ExtrapolatedGroup& g = groups[k];
        std::printf("  %-6s N = %-7lld phi = %-8g %6lld replicas %5.1f%% of the work, from the %s", g.model.c_str(),
                    static_cast<long long>(g.n), g.phi, static_cast<long long>(g.replicas),
                    100.0 * g.seconds / std::max(1e-300, total_seconds), g.from.c_str());
        if (g.probe_budget > 0)  // a minimisation extrapolated in N can be several times off
            std::printf(" (--probe-seconds %.0f would probe it)", std::ceil(g.probe_budget / 10) * 10);
        std::printf("\n");
    }
    if (groups.size() > kShown) {
        double rest = 0;
        for (std::size_t k = kShown; k < groups.size(); ++k) rest += groups[k].seconds;
        std::printf("  and %zu more groups with %.1f%% of the work\n", groups.size() - kShown,
                    100.0 * rest / std::max(1e-300, total_seconds));
    }
}

}  // namespace

void print_dry_run(const CampaignSpec& spec, const std::string& output, const DryRunPlan& plan) {
    std::printf("campaign %s: %s -> %s (dry run: nothing written)\n", spec.name.c_str(),
                counted(static_cast<long long>(spec.replicas.size()), "replica").c_str(), output.c_str());
    const ReplicaSeconds estimate = replica_seconds(spec, output, plan.calibrate, plan.probe_seconds, true);
    double total = 0, largest = 0;
    for (const double seconds : estimate.seconds) {
        total += seconds;
        largest = std::max(largest, seconds);
    }
    if (plan.summary) {
        print_groups(spec, estimate.seconds);
    } else {
        std::printf("%6s %7s %8s %10s %6s %9s %14s %10s %9s\n", "id", "N", "phi", "rate", "seed", "samples",
                    "cost(p-evals)", "est. s", "sampling");
        for (std::size_t id = 0; id < spec.replicas.size(); ++id) {
            const ReplicaParams& p = spec.replicas[id];
            // phi and rate as the campaign gives them (show_value: the shortest text that reads
            // back the same; %.4g showed 0.8401 and 0.84012 alike)
            std::printf("%6zu %7lld %8s %10s %6llu %9lld %14.4g %10.6g %9.6g\n", id, static_cast<long long>(p.n),
                        show_value(p.phi).c_str(), show_value(p.rate).c_str(), static_cast<unsigned long long>(p.seed),
                        static_cast<long long>(sample_count(p)), estimated_cost(p), estimate.seconds[id],
                        estimate.serial[id]);
        }
    }
    std::printf("total: %.3g core-hours, %.3g core-seconds on one thread (%s; the longest replica: %s)\n",
                total / 3600.0, total, estimate.source.c_str(), duration(largest).c_str());
    print_extrapolated(estimate.extrapolated, total);
    // A resumed or grown archive: what its finished replicas leave to run.
    std::error_code ec;
    if (std::filesystem::exists(output, ec) && diagnose_archive_file(output).empty()) try {
            const StoredCampaign stored = read_stored_campaign(output);
            std::set<std::string> finished;
            for (std::size_t r = 0; r < stored.status.size(); ++r)
                if (stored.status[r] == ReplicaStatus::Done || stored.status[r] == ReplicaStatus::Failed)
                    finished.insert(describe(stored.spec.replicas[r]));
            double left = 0;
            for (std::size_t r = 0; r < spec.replicas.size(); ++r)
                if (!finished.count(describe(spec.replicas[r]))) left += estimate.seconds[r];
            std::printf("left to run: %.3g core-seconds (the archive's %zu finished replicas are kept)\n", left,
                        finished.size());
        } catch (const std::exception&) {
            // an archive that cannot be read was refused before a dry run lists anything
        }
    print_wall_time(spec, estimate.seconds, estimate.serial,
                    WallTimePlan{.ranks = plan.ranks,
                                 .threads = kernel_threads(),
                                 .shards = plan.shards,
                                 .time_limit = plan.time_limit,
                                 .signal_lead = plan.signal_lead,
                                 .speedup = SpeedupModel{.serial_fraction = plan.serial_fraction}});
}

double signal_lead_from_environment() {
    const char* text = std::getenv("JAMSIM_SIGNAL_LEAD");
    if (!text) return kDefaultSignalLead;
    const std::string v(text);
    // As slurm/submit_campaign.sh demands: digits, no leading zero, and at most sbatch
    // --signal's largest sig_time, 65535.
    const bool digits =
        !v.empty() && v.size() <= 5 && v[0] != '0' && v.find_first_not_of("0123456789") == std::string::npos;
    if (!digits || std::stod(v) > 65535)
        throw CLI::ValidationError("jamsim run: JAMSIM_SIGNAL_LEAD = '" + v +
                                   "' is not allowed: seconds of Slurm's warning before the time limit, a whole "
                                   "number from 1 to 65535 (as slurm/submit_campaign.sh passes it to sbatch --signal)");
    return std::stod(v);
}

}  // namespace jamsim::app
