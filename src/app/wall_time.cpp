// A campaign's wall time from the farm's scheduler simulated (wall_time.hpp).
#include "wall_time.hpp"

#include "jamsim/campaign/wall_time.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "jamsim/run/model_registry.hpp"

namespace jamsim::app {

namespace {

/// The shards' table and the busiest task's requeues under plan.time_limit.
void print_shards(const CampaignSpec& spec, const Chains& chains, const std::vector<SimulatedReplica>& replicas,
                  const WallTimePlan& plan) {
    const double lead = plan.signal_lead;
    const double usable = plan.time_limit - lead - 60.0;  // Slurm may warn a minute early; run refuses <= 0
    const auto requeues = [&](double seconds) {
        return plan.time_limit > 0 ? static_cast<int>(std::max(0.0, std::ceil(seconds / usable) - 1.0)) : 0;
    };
    std::printf("shards: %s of %s x %s, rate ladders kept whole (chain %% %d):\n",
                counted(plan.shards, "Slurm task").c_str(), counted(plan.ranks, "rank").c_str(),
                counted(plan.threads, "thread").c_str(), plan.shards);
    std::printf("%6s %7s %9s %14s %14s %14s %9s\n", "shard", "chains", "replicas", "work (core-h)", "critical path",
                "makespan", "requeues");
    double worst = 0;
    for (int k = 0; k < plan.shards; ++k) {
        std::vector<std::int64_t> ids;
        std::int64_t count = 0;
        for (std::size_t c = k; c < chains.members.size(); c += static_cast<std::size_t>(plan.shards)) {
            ids.insert(ids.end(), chains.members[c].begin(), chains.members[c].end());
            ++count;
        }
        std::sort(ids.begin(), ids.end());
        const SimulatedRun run = simulate_part(spec, replicas, ids, plan.ranks, plan.threads);
        worst = std::max(worst, run.makespan);
        const std::string name = std::to_string(k) + "/" + std::to_string(plan.shards);  // as --shard K/S
        std::printf("%6s %7lld %9zu %14.4g %14s %14s %9d\n", name.c_str(), static_cast<long long>(count), ids.size(),
                    run.work / 3600, duration(run.critical_path).c_str(), duration(run.makespan).c_str(),
                    requeues(run.makespan));
    }
    std::printf("wall time with every task running at once: about %s (%.0f s)\n", duration(worst).c_str(), worst);
    if (plan.time_limit > 0)
        std::printf("%s on %s each, time limit %s (warning %.0f s before): the busiest task needs about %s, %s\n",
                    counted(plan.shards, "shard").c_str(), counted(plan.ranks, "rank").c_str(),
                    duration(plan.time_limit).c_str(), lead, duration(worst).c_str(),
                    counted(requeues(worst), "requeue").c_str());
}

}  // namespace

void print_wall_time(const CampaignSpec& spec, const std::vector<double>& seconds, const std::vector<double>& serial,
                     const WallTimePlan& plan) {
    const Chains chains = chains_of(spec.predecessor, spec.replicas.size());
    const auto replicas = simulated_replicas(spec, seconds, serial, plan.threads, plan.speedup);
    const SimulatedRun run = simulate_schedule(replicas, spec.predecessor, plan.ranks, plan.threads);
    if (run.longest_chain < 0) return;  // no replicas
    double chain_seconds = 0;           // the longest chain on one thread
    for (const std::int64_t r : chains.members[static_cast<std::size_t>(run.longest_chain)])
        chain_seconds += seconds[static_cast<std::size_t>(r)];
    const int cores = plan.ranks * plan.threads;
    std::printf("threads: %d per rank; a replica's speed-up on them: %s\n", plan.threads,
                describe_speedup(plan.speedup).c_str());
    std::printf("critical path: %s (%.0f s) on %s: %s, %s on one thread\n", duration(run.critical_path).c_str(),
                run.critical_path, counted(plan.threads, "thread").c_str(),
                describe_chain(spec, chains, run.longest_chain).c_str(), duration(chain_seconds).c_str());
    const auto at_once = static_cast<long long>(run.chains);
    std::printf("at once: at most %s run together (%s), so at most %s x %s = %s\n", counted(at_once, "replica").c_str(),
                counted(at_once, spec.predecessor.empty() ? "independent replica" : "chain").c_str(),
                counted(at_once, "rank").c_str(), counted(plan.threads, "thread").c_str(),
                counted(at_once * plan.threads, "core").c_str());
    std::printf("wall time on %s x %s: about %s (%.0f s; the farm's scheduler simulated on these "
                "costs); no schedule beats %s = max(work / %s = %s, critical path = %s); cores idle: "
                "%.3g core-hours, %.0f%%\n",
                counted(plan.ranks, "rank").c_str(), counted(plan.threads, "thread").c_str(),
                duration(run.makespan).c_str(), run.makespan, duration(run.bound).c_str(),
                counted(cores, "core").c_str(), duration(run.work / cores).c_str(), duration(run.critical_path).c_str(),
                run.idle_core_seconds / 3600, 100 * run.idle_core_seconds / std::max(1e-300, cores * run.makespan));
    if (plan.shards > 1 || plan.time_limit > 0) print_shards(spec, chains, replicas, plan);
}

namespace {

/// A number option `name` into `value`, refused outside [lowest, highest] with one message
/// that says what is allowed (`allowed`).
void add_bounded_number(CLI::App& command, const std::string& name, double& value, double lowest, double highest,
                        const std::string& allowed, const std::string& help, const std::string& type) {
    command
        .add_option_function<std::string>(
            name,
            [&value, name, lowest, highest, allowed](const std::string& text) {
                char* end = nullptr;
                const double v = std::strtod(text.c_str(), &end);
                if (text.empty() || *end != '\0' || !(v >= lowest && v <= highest))
                    throw CLI::ValidationError(name + " = " + text + " is not allowed: " + allowed);
                value = v;
            },
            help)
        ->type_name(type);
}

}  // namespace

void add_serial_fraction_option(CLI::App& command, double& fraction) {
    add_bounded_number(command, "--serial-fraction", fraction, 0, 1,
                       "a number from 0 to 1 (the part of a replica's time that does not speed up on threads)",
                       "The wall-time estimate's speed-up on threads: Amdahl's law with this serial fraction for "
                       "every N and model (default: each model's kernel's, measured, by N)",
                       "F");
}

void add_probe_seconds_option(CLI::App& command, double& seconds) {
    add_bounded_number(command, "--probe-seconds", seconds, 0, 1e6,
                       "seconds from 0 to 1e6 (the calibration's probe budget; 0: no probes)",
                       "Seconds the cost calibration may spend probing (default 30): groups past it are "
                       "extrapolated from those measured, and listed",
                       "SECONDS");
}

}  // namespace jamsim::app
