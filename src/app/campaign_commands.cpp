#include "campaign_commands.hpp"
#include "threads_option.hpp"

#include <unistd.h>

#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <memory>
#include <set>
#include <queue>
#include <tuple>
#include <algorithm>
#include <ctime>
#include <functional>
#include <sstream>
#include <limits>

#include "jamsim/campaign/stop_request.hpp"
#include "jamsim/io/archive.hpp"
#include "jamsim/io/capacity.hpp"
#include "jamsim/io/archive_file_check.hpp"
#include "jamsim/io/archive_lock.hpp"
#include "jamsim/io/checkpoint_file.hpp"
#include "jamsim/io/initial_states.hpp"
#include "jamsim/io/campaign_spec.hpp"
#include "jamsim/linalg/contact_solver.hpp"
#include "jamsim/campaign/farm.hpp"
#include "jamsim/params/parameters.hpp"
#include "jamsim/run/model_registry.hpp"
#include "jamsim/parallel/mpi.hpp"

namespace jamsim::app {

namespace {

/// What --dry-run estimates for.
struct DryRunPlan {
    bool calibrate = true;
    int ranks = 1;           ///< ranks of the planned run
    int shards = 1;          ///< Slurm array tasks
    double time_limit = 0;   ///< seconds per task (0: none)
};

struct RunOptions {
    std::string spec_path;
    std::string output;  // overrides [campaign] output
    bool dry_run = false;
    double progress_interval = 10.0;
    std::string progress = "auto";  // auto | lines | redraw
    std::string shard;              // "K/N" or empty
    bool retry_failed = false;      // run failed replicas again
    double checkpoint_seconds = 300;  // save a running replica's state at most this often
    DryRunPlan plan;                  // what --dry-run estimates for
    std::int64_t max_replicas = kDefaultMaxReplicas;
    CapacityLimits limits;
};

/// Exit status of a run that was interrupted (a signal) with every running replica's state
/// saved: run the same command again to continue (the Slurm scripts requeue on it).
constexpr int kExitInterrupted = 75;

/// "90", "90s", "15min", "2h" in seconds; negative when it does not parse.
double parse_duration(const std::string& text) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    const std::string unit(end);
    const double scale = unit.empty() || unit == "s" ? 1.0 : unit == "min" ? 60.0 : unit == "h" ? 3600.0 : -1.0;
    if (end == text.c_str() || scale < 0 || !std::isfinite(v) || v < 0) return -1.0;
    return v * scale;
}

/// "K/N" with 0 <= K < N, or an exception naming the value.
Shard parse_shard(const std::string& text) {
    Shard s;
    char slash = 0;
    std::istringstream in(text);
    if (text.empty()) return s;
    if (!(in >> s.index >> slash >> s.count) || slash != '/' || !in.eof() || s.count < 1 ||
        s.index < 0 || s.index >= s.count)
        throw CLI::ValidationError("jamsim run: --shard = " + text +
                                   " is not allowed: K/N with 0 <= K < N (e.g. 3/16)");
    return s;
}

/// Under mpirun a rank's stdout is a pseudo-terminal even when the job's output goes to a
/// file, so `auto` redraws only for a single process on a terminal outside batch jobs and CI;
/// `--progress redraw` asks for it explicitly.
bool redraw_progress(const std::string& mode) {
    if (mode != "auto") return mode == "redraw";
    return isatty(STDOUT_FILENO) != 0 && !std::getenv("OMPI_COMM_WORLD_SIZE") &&
           !std::getenv("PMI_RANK") && !std::getenv("SLURM_JOB_ID") && !std::getenv("CI");
}


/// What a run does with an existing archive of its campaign.
enum class OutputMode : int { Fresh = 0, Extend = 1, Grow = 2 };

/// "" when the run may write `path`; `mode` says how (a new or resumed archive, one extended
/// to longer runs, one grown by more replicas: then `source` maps spec's replicas to the
/// archive's, Archive::check_growth).
std::string check_output(const std::string& path, const CampaignSpec& spec, OutputMode& mode,
                         std::vector<std::int64_t>& source) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::exists(path, ec)) {
        if (fs::is_directory(path, ec))
            return spec.path + ": [campaign] output = \"" + path +
                   "\" is not allowed: a file path, not a directory";
        if (const std::string bad = diagnose_archive_file(path); !bad.empty())
            return spec.path + ": refusing to use the archive: " + bad +
                   " (choose another [campaign] output or -o, or remove the file)";
        const std::string why = Archive::check_existing(path, spec);
        if (why.empty()) return "";
        if (why.find("belongs to a different campaign") == std::string::npos)  // another version, unreadable
            return spec.path + ": refusing to use the archive: " + why +
                   " (choose another [campaign] output or -o)";
        const std::string not_longer = Archive::check_extension(path, spec);
        if (not_longer.empty()) {  // the same campaign, run longer
            mode = OutputMode::Extend;
            return "";
        }
        if (not_longer.find("would run shorter") != std::string::npos)  // the one near miss
            return spec.path + ": refusing to use the archive '" + path + "': " + not_longer +
                   " than in it: a campaign can be extended to a larger strain (or time), not "
                   "shortened (choose another [campaign] output or -o)";
        const std::string not_grown = Archive::check_growth(path, spec, source);
        if (not_grown.empty()) {  // the same campaign with more replicas
            mode = OutputMode::Grow;
            return "";
        }
        return spec.path + ": refusing to use the archive: '" + path +
               "' belongs to a different campaign: " + not_grown +
               " (choose another [campaign] output or -o)";
    }
    // Checkpoints without their archive belong to a run whose archive was removed or moved:
    // a new campaign must not continue from them.
    if (const std::string folder = checkpoint_folder(path);
        fs::is_directory(folder, ec) && !fs::is_empty(folder, ec))
        return spec.path + ": refusing to start '" + path + "': the checkpoint folder '" + folder +
               "' of an earlier run is there without its archive (restore the archive to "
               "continue that run, or remove the folder to start afresh)";
    const fs::path p(path);
    const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    if (!fs::is_directory(dir, ec) || ::access(dir.c_str(), W_OK) != 0)
        return spec.path + ": [campaign] output = \"" + path +
               "\" is not allowed: a file in an existing writable directory ('" + dir.string() +
               "' is not)";
    return "";
}

/// Every checkpoint beside the archive must belong to one of this campaign's replicas, so a
/// stale or foreign one stops the run before any work (it is left as it is). A damaged one
/// (unreadable) is left to its replica, which warns, removes it and starts again.
std::string check_checkpoints(const std::string& output, const CampaignSpec& spec) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path folder = checkpoint_folder(output);
    if (!fs::is_directory(folder, ec)) return "";
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
        const std::string name = entry.path().filename().string();
        long long id = -1;
        char tail[8] = {};
        if (std::sscanf(name.c_str(), "replica_%lld.h%7s", &id, tail) != 2 || std::string(tail) != "5")
            continue;  // not a checkpoint (e.g. a .tmp left by a kill)
        if (id < 0 || id >= static_cast<long long>(spec.replicas.size()))
            return spec.path + ": checkpoint '" + entry.path().string() + "' names replica " +
                   std::to_string(id) + ", this campaign has " +
                   std::to_string(spec.replicas.size()) + ": remove it or choose another output";
        try {
            check_checkpoint_header(entry.path().string(), spec.replicas[static_cast<std::size_t>(id)]);
        } catch (const CheckpointUnreadable&) {
            continue;  // damaged: its replica removes it with a warning and starts again
        } catch (const CheckpointError& e) {
            return spec.path + ": " + e.what();
        }
    }
    return "";
}

/// "" when every replica of the archive at `output` that started from [run] initial would
/// start from the same state today (grow_source: the archive's id of each replica of a grown
/// campaign, empty otherwise); else which would not, and what to do.
std::string initial_source_changed(const InitialStates& source, const CampaignSpec& spec, const std::string& output,
                                   const std::vector<std::int64_t>& grow_source) {
    InitialRecords recorded = read_initial_records(output);
    if (!grow_source.empty()) {  // to this campaign's ids
        InitialRecords mapped;
        for (const std::int64_t from : grow_source) {
            const bool kept = from >= 0 && static_cast<std::size_t>(from) < recorded.source.size();
            mapped.source.push_back(kept ? recorded.source[static_cast<std::size_t>(from)] : 0);
            mapped.state.push_back(kept ? recorded.state[static_cast<std::size_t>(from)] : 0);
        }
        recorded = std::move(mapped);
    }
    const std::string why = source.changed_since(spec.replicas, recorded.source, recorded.state);
    return why.empty() ? "" : spec.path + ": " + why;
}

/// `path` as MPI-IO is given it: Open MPI's MPI-IO overflows a buffer (and aborts the job)
/// on names of more than about 245 characters, so a longer one is given relative to the
/// working directory, and one that is long even so is refused with jamsim's words.
std::string mpi_io_path(const std::string& spec_path, const std::string& path) {
    constexpr std::size_t kLongest = 240;
    if (path.size() <= kLongest) return path;
    std::error_code ec;
    const std::string relative = std::filesystem::proximate(path, ec).string();
    if (!ec && relative.size() <= kLongest) return relative;
    throw SpecError(spec_path + ": output = \"" + path.substr(0, 60) + "...\" (" + std::to_string(path.size()) +
                    " characters) is not allowed: an archive path of at most " + std::to_string(kLongest) +
                    " characters (Open MPI's MPI-IO takes no longer names), also relative to the working directory; "
                    "run from a folder nearer the archive, or choose a shorter path");
}

/// PETSc options (campaign-wide, [model] petsc_options) that PETSc does not recognise or the
/// CD0 solver does not use: refused before any work, by PETSc itself (the table's check has
/// refused those no PETSc solver would see).
std::string check_petsc_options(const CampaignSpec& spec) {
    for (const ReplicaParams& p : spec.replicas) {
        if (p.petsc_options.empty() || !uses_parameter(p, "petsc_options")) continue;
        try {
            if (const std::string why = linalg::petsc_options_problem(p.petsc_options); !why.empty())
                return spec.path + ": [model] petsc_options = \"" + p.petsc_options +
                       "\" is not allowed: " + why;
        } catch (const std::exception& e) {
            return spec.path + ": [model] petsc_options = \"" + p.petsc_options +
                   "\" could not be checked: " + e.what();
        }
        return "";  // the same options for every replica: one check
    }
    return "";
}

/// Advisory warnings (limits not refused), each kind once in the run log; the archive keeps
/// them too (its root attribute `warnings`).
void print_advisories(const CampaignSpec& spec) {
    for (const std::string& line : campaign_warnings(spec))
        std::fprintf(stderr, "jamsim run: warning: %s: %s\n", spec.path.c_str(), line.c_str());
    // A file without [run] is allowed, but the length and sampling of a dynamics run are
    // then the defaults: say which, so that an omission is not mistaken for a choice.
    if (spec.run_table || spec.replicas.empty()) return;
    std::string defaults;
    for (const auto& info : parameters()) {
        if (info.table != "run" || (info.key != "strain" && info.key != "time" && info.key != "transient" &&
                                    info.key != "sample_interval"))
            continue;
        const auto used = std::find_if(spec.replicas.begin(), spec.replicas.end(),
                                       [&](const ReplicaParams& p) { return uses_parameter(p, info.key); });
        if (used == spec.replicas.end()) continue;
        defaults.append(defaults.empty() ? "" : ", ").append(info.key).append(" = ").append(
            show_value(get_value(*used, info)));
    }
    if (!defaults.empty())
        std::fprintf(stderr, "jamsim run: warning: %s: no [run] table: the run takes the defaults %s "
                     "(campaigns/TEMPLATE.toml lists every key)\n", spec.path.c_str(), defaults.c_str());
}

/// Replicas that run at one throughput (seconds per estimated cost unit): model, N and phi.
using CostGroup = std::tuple<std::string, std::int64_t, double>;
CostGroup cost_group(const ReplicaParams& p) { return {p.model, p.n, p.phi}; }

/// Seconds per estimated cost unit on this machine, per group, and where they come from.
struct Calibration {
    std::map<CostGroup, double> measured;  ///< groups measured (recorded or probed)
    int recorded = 0, probed = 0;          ///< groups from an earlier run's archive, from probes

    /// A group measured, else the model's measured groups (the same N first), else nominal.
    double seconds_per_cost(const ReplicaParams& p) const {
        if (const auto it = measured.find(cost_group(p)); it != measured.end()) return it->second;
        double same_n = 0, same_model = 0;
        int n_count = 0, model_count = 0;
        for (const auto& [group, rate] : measured) {
            if (std::get<0>(group) != p.model) continue;
            same_model += rate;
            ++model_count;
            if (std::get<1>(group) == p.n) {
                same_n += rate;
                ++n_count;
            }
        }
        if (n_count > 0) return same_n / n_count;
        if (model_count > 0) return same_model / model_count;
        return 1.0 / kNominalEvaluationsPerSecond;
    }
};

/// CPU seconds this process has used.
double process_cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// Seconds of probes a dry run may spend calibrating (the groups left use measured neighbours).
constexpr double kProbeBudgetSeconds = 30.0;

/// The throughput of each group of a campaign on this machine: from the replicas an earlier
/// run finished in the campaign's archive (wall time over estimated cost), else from a probe
/// of the group's first replica (process CPU time): dynamics run it for about 1e7 and 3e7
/// particle force evaluations and take the difference (at least 20 steps; the replica whole
/// when shorter), a minimisation protocol up to three of
/// its replicas whole, each when it takes under 10 s by the best estimate so far (a
/// minimisation's cost depends on N, phi and the seed in ways its estimate counts only
/// roughly). Probes stop after kProbeBudgetSeconds.
Calibration calibrate(const CampaignSpec& spec, const std::string& archive) {
    Calibration out;
    // Rates recorded by earlier runs of this campaign (or of the archive's campaign, grown).
    std::map<CostGroup, std::pair<double, double>> recorded;  // group -> (seconds, cost)
    std::error_code ec;
    if (!archive.empty() && std::filesystem::exists(archive, ec) && diagnose_archive_file(archive).empty()) try {
            const StoredCampaign stored = read_stored_campaign(archive);
            const h5::Handle file = h5::open_unlocked_readonly(archive);
            const auto wall = h5::read_all<double>(file.get(), "/replicas/wall_seconds", H5T_NATIVE_DOUBLE);
            for (std::size_t r = 0; r < stored.status.size() && r < wall.size(); ++r) {
                const ReplicaParams& p = stored.spec.replicas[r];
                if (stored.status[r] != ReplicaStatus::Done || !(wall[r] > 0) || !(estimated_cost(p) > 0)) continue;
                auto& [seconds, cost] = recorded[cost_group(p)];
                seconds += wall[r];
                cost += estimated_cost(p);
            }
        } catch (const std::exception&) {
            recorded.clear();  // an archive that cannot be read: probes instead
        }
    for (const auto& [group, sums] : recorded) {
        out.measured[group] = sums.first / sums.second;
        ++out.recorded;
    }
    double spent = 0;
    // Minimisations: up to kMinimisationProbes replicas (seeds) per group, their mean, since
    // a minimisation's cost varies from seed to seed (near phi_J by an order of magnitude).
    constexpr int kMinimisationProbes = 3;
    std::map<CostGroup, std::pair<double, double>> probed;  // group -> (seconds, cost)
    std::map<CostGroup, int> probes;
    for (const ReplicaParams& p : spec.replicas) {
        const CostGroup key = cost_group(p);
        const bool minimisation = model_of(p).kind != ModelKind::Dynamics;
        if (recorded.count(key) || spent >= kProbeBudgetSeconds ||
            probes[key] >= (minimisation ? kMinimisationProbes : 1))
            continue;
        const bool dynamics = model_of(p).kind == ModelKind::Dynamics;
        // A dynamics probe runs the replica for `steps` and for 3 × `steps` and takes the
        // difference, so that the set-up (initial state, first list, first factorisation)
        // is not spread over a few hundred steps; a replica shorter than that runs whole.
        auto shortened = [&](double steps) {
            ReplicaParams probe = p;
            (p.rate > 0 ? probe.strain : probe.time) = steps * p.dt * (p.rate > 0 ? p.rate : 1.0);
            probe.sample_interval = probe.rate > 0 ? probe.strain : probe.time;
            probe.transient = 0.0;  // the probe is shorter than the replica's transient may be
            probe.checkpoint_steps = 1'000'000'000;
            return probe;
        };
        std::vector<ReplicaParams> runs{p};
        if (dynamics) {
            const double steps = std::max(20.0, 1e7 / (static_cast<double>(p.n) * evaluations_per_step(p)));
            if (3 * steps < static_cast<double>(schedule_of(p).steps)) runs = {shortened(steps), shortened(3 * steps)};
        } else if (estimated_cost(p) * out.seconds_per_cost(p) > std::min(10.0, kProbeBudgetSeconds - spent)) {
            continue;
        }
        try {
            // Process CPU time, not wall time: other jobs on a shared machine (a login node,
            // a laptop) would otherwise inflate the estimate for the cluster node it is for.
            std::vector<std::pair<double, double>> measured;  // (CPU seconds, cost) per run
            for (const ReplicaParams& run : runs) {
                const double t0 = process_cpu_seconds();
                const ReplicaResult r = run_replica(run);
                const double seconds = process_cpu_seconds() - t0;
                spent += r.wall_seconds;
                const double cost = dynamics ? static_cast<double>(r.force_evaluations) * static_cast<double>(p.n)
                                             : estimated_cost(p);
                measured.emplace_back(seconds, cost);
            }
            double seconds = measured.back().first, cost = measured.back().second;
            if (measured.size() == 2 && measured[1].first > measured[0].first && measured[1].second > measured[0].second) {
                seconds = measured[1].first - measured[0].first;
                cost = measured[1].second - measured[0].second;
            }
            if (cost > 0 && seconds > 0) {
                auto& [sum_seconds, sum_costs] = probed[key];
                sum_seconds += seconds;
                sum_costs += cost;
                out.measured[key] = sum_seconds / sum_costs;
                ++probes[key];
            }
        } catch (const std::exception&) {
            // a probe that fails (a replica that would fail) leaves its group to the others
        }
    }
    out.probed = static_cast<int>(probed.size());
    return out;
}

/// "42 s", "12.5 min", "3.20 h".
std::string duration(double seconds) {
    char buf[32];
    if (seconds < 120) std::snprintf(buf, sizeof buf, "%.1f s", seconds);
    else if (seconds < 7200) std::snprintf(buf, sizeof buf, "%.1f min", seconds / 60);
    else std::snprintf(buf, sizeof buf, "%.2f h", seconds / 3600);
    return buf;
}

void print_dry_run(const CampaignSpec& spec, const std::string& output, const DryRunPlan& plan) {
    std::printf("campaign %s: %zu replicas -> %s (dry run: nothing written)\n", spec.name.c_str(),
                spec.replicas.size(), output.c_str());
    const Calibration rates = plan.calibrate ? calibrate(spec, output) : Calibration{};
    const auto seconds_of = [&](const ReplicaParams& p) { return estimated_cost(p) * rates.seconds_per_cost(p); };
    std::printf("%6s %7s %8s %10s %6s %9s %14s %10s\n", "id", "N", "phi", "rate", "seed",
                "samples", "cost(p-evals)", "est. s");
    double total = 0, largest = 0;
    std::vector<double> shard_seconds(static_cast<std::size_t>(plan.shards), 0.0);
    for (std::size_t id = 0; id < spec.replicas.size(); ++id) {
        const ReplicaParams& p = spec.replicas[id];
        const double seconds = seconds_of(p);
        total += seconds;
        largest = std::max(largest, seconds);
        shard_seconds[id % shard_seconds.size()] += seconds;
        std::printf("%6zu %7lld %8.4g %10.3g %6llu %9lld %14.4g %10.1f\n", id,
                    static_cast<long long>(p.n), p.phi, p.rate,
                    static_cast<unsigned long long>(p.seed),
                    static_cast<long long>(sample_count(p)), estimated_cost(p), seconds);
    }
    // The wall time on P ranks: the farm's schedule, longest estimated cost first, each replica
    // to the rank that becomes free first.
    std::vector<double> by_cost;
    for (const ReplicaParams& p : spec.replicas) by_cost.push_back(seconds_of(p));
    std::sort(by_cost.begin(), by_cost.end(), std::greater<>());
    std::priority_queue<double, std::vector<double>, std::greater<>> free_at;
    for (int r = 0; r < plan.ranks; ++r) free_at.push(0.0);
    double wall = 0;
    for (const double seconds : by_cost) {
        const double start = free_at.top();
        free_at.pop();
        free_at.push(start + seconds);
        wall = std::max(wall, start + seconds);
    }
    const std::string source =
        !plan.calibrate ? "nominal 7e7 particle force evaluations/s"
                        : "throughput measured on this machine per model, N and phi: " + std::to_string(rates.recorded) +
                              " groups from the archive's finished replicas, " + std::to_string(rates.probed) +
                              " by a short probe, the rest from those";
    std::printf("total: %.3g core-hours, %.3g core-seconds (%s); on %d ranks about %s of wall time (the longest "
                "replica: %s)\n",
                total / 3600.0, total, source.c_str(), plan.ranks, duration(wall).c_str(), duration(largest).c_str());
    // A resumed or grown archive: what its finished replicas leave to run.
    std::error_code ec;
    if (std::filesystem::exists(output, ec) && diagnose_archive_file(output).empty()) try {
            const StoredCampaign stored = read_stored_campaign(output);
            std::set<std::string> finished;
            for (std::size_t r = 0; r < stored.status.size(); ++r)
                if (stored.status[r] == ReplicaStatus::Done || stored.status[r] == ReplicaStatus::Failed)
                    finished.insert(describe(stored.spec.replicas[r]));
            double left = 0;
            for (const ReplicaParams& p : spec.replicas)
                if (!finished.count(describe(p))) left += seconds_of(p);
            std::printf("left to run: %.3g core-seconds (the archive's %zu finished replicas are kept)\n", left,
                        finished.size());
        } catch (const std::exception&) {
            // an archive that cannot be read was refused before a dry run lists anything
        }
    if (plan.time_limit > 0) {
        const char* lead_env = std::getenv("JAMSIM_SIGNAL_LEAD");
        const double lead = lead_env ? std::atof(lead_env) : 300.0;
        const double usable = plan.time_limit - lead - 60.0;  // Slurm may warn a minute early
        if (usable <= 0) {
            std::printf("time limit %.0f s: not above the warning lead %.0f s + 60 s; no task can work\n",
                        plan.time_limit, lead);
            return;
        }
        double worst = 0;
        for (double s : shard_seconds) worst = std::max(worst, s / plan.ranks);
        std::printf("%d shards on %d ranks each, time limit %s (warning %.0f s before): the "
                    "busiest task needs about %s, %d requeues\n",
                    plan.shards, plan.ranks, duration(plan.time_limit).c_str(), lead, duration(worst).c_str(),
                    static_cast<int>(std::max(0.0, std::ceil(worst / usable) - 1.0)));
    }
}

/// The filesystem of `path` has (almost) no space left: a failed write is a full disk.
bool disk_full(const std::string& path) {
    const double free = free_bytes(path);
    return std::isfinite(free) && free < 1e6;
}

void print_capacity(const CapacityEstimate& e, const std::string& output) {
    std::printf("archive %s: %s when complete (%s on disk now), checkpoints up to %s, %s free on its "
                "filesystem; memory: about %s per rank, %d ranks on a node of %s available\n",
                output.c_str(), show_bytes(e.archive_bytes).c_str(), show_bytes(e.archive_present).c_str(),
                show_bytes(e.checkpoint_bytes).c_str(), show_bytes(e.free_bytes).c_str(),
                show_bytes(e.rank_memory).c_str(), e.ranks_per_node, show_bytes(e.node_memory).c_str());
    if (e.frame_bytes > 0)
        std::printf("configuration frames ([run] frame_interval): up to %.0f per replica, %s of the archive\n",
                    e.frames, show_bytes(e.frame_bytes).c_str());
}

int run(const RunOptions& opt, int& argc, char**& argv) {
    mpi::Session session(argc, argv);
    const linalg::PetscScope petsc;  // finalised before MPI (declared after the session)
    StopRequest::install();          // PETSc is started with -no_signal_handler
    const MPI_Comm comm = MPI_COMM_WORLD;
    const int rank = mpi::rank(comm);
    // Rank 0 reads and checks everything before any rank starts work.
    std::string text, error, output = opt.output;
    int extend = 0;  // the archive holds this campaign with shorter runs: extend it
    int grow = 0;    // the archive holds this campaign with fewer replicas: grow it
    std::vector<std::int64_t> grow_source;  // rank 0: the archive's id of each replica (−1: new)
    std::int64_t grow_kept = 0;
    const int node_ranks = opt.dry_run ? opt.plan.ranks : mpi::ranks_on_node(comm);
    const int ranks = opt.dry_run ? opt.plan.ranks : mpi::size(comm);
    if (rank == 0) {
        try {
            const CampaignSpec spec = load_campaign(opt.spec_path, opt.max_replicas);
            text = spec.text;
            if (output.empty()) output = spec.output;
            // An archive reached through a symlink is the file it names: its lock, checkpoints
            // and growth files are those of that file, whichever path a run was given.
            if (std::error_code ec; std::filesystem::is_symlink(output, ec)) {
                const auto target = std::filesystem::weakly_canonical(output, ec);
                if (!ec) output = target.string();
            }
            output = mpi_io_path(spec.path, output);
            // Size and memory before anything is created (the dry run prints them).
            const CapacityEstimate capacity = estimate_capacity(spec, output, ranks, node_ranks);
            if (opt.dry_run) print_capacity(capacity, output);
            error = check_capacity(capacity, opt.limits, spec, output);
            if (!error.empty() && opt.dry_run) {
                std::printf("the run would be refused: %s\n", error.c_str());
                error.clear();
            }
            if (!error.empty()) throw SpecError(error);
            // A growth that a kill interrupted is completed (after its rename) or undone
            // (before it) first, unless another live run holds the archive (refused below).
            if (!opt.dry_run) try {
                    ArchiveLock::check_free(output);
                    if (const std::string done = Archive::finish_growth(output); !done.empty())
                        std::printf("jamsim run: %s\n", done.c_str());
                } catch (const ArchiveBusy&) {
                } catch (const h5::Error& e) {
                    throw SpecError(spec.path + ": " + e.what());
                }
            // A dry run writes nothing, but an existing archive it names must fit the campaign.
            OutputMode mode = OutputMode::Fresh;
            if (!opt.dry_run || std::filesystem::exists(output)) error = check_output(output, spec, mode, grow_source);
            extend = mode == OutputMode::Extend;
            grow = mode == OutputMode::Grow;
            for (const std::int64_t from : grow_source) grow_kept += from >= 0;
            // The checkpoints beside the archive are keyed by its replica ids (before a growth,
            // those of the archive's campaign).
            if (error.empty())
                error = check_checkpoints(output, grow ? read_stored_campaign(output).spec : spec);
            if (error.empty()) error = check_petsc_options(spec);
            if (error.empty()) print_advisories(spec);
            if (error.empty() && !spec.replicas.front().initial.empty()) {
                try {  // every replica must find its starting state before any work
                    const InitialStates source(spec.replicas.front().initial);
                    for (std::size_t id = 0; id < spec.replicas.size(); ++id)
                        source.match(spec.replicas[id], static_cast<std::int64_t>(id));
                    if (std::filesystem::exists(output)) error = initial_source_changed(source, spec, output, grow_source);
                } catch (const InitialStateError& e) {
                    error = spec.path + ": " + e.what();
                }
            }
        } catch (const SpecError& e) {
            error = e.what();
        } catch (const std::exception& e) {  // any other failure of rank 0's checks (an unreadable
            error = opt.spec_path + ": " + e.what();  // file): said on every rank, never left unbroadcast
        }
        // An archive that another live run writes is refused for that reason, whatever it
        // looks like now (it may be half created): the holder's name says what to do.
        if (!opt.dry_run && !output.empty()) try {
                ArchiveLock::check_free(output);
            } catch (const ArchiveBusy& e) {
                error = e.what();
            }
    }
    mpi::broadcast(error, 0, comm);
    if (!error.empty()) {
        if (rank == 0) std::fprintf(stderr, "jamsim run: %s\n", error.c_str());
        return 2;
    }
    mpi::broadcast(text, 0, comm);
    mpi::broadcast(output, 0, comm);
    mpi::broadcast(extend, 0, comm);
    mpi::broadcast(grow, 0, comm);
    const CampaignSpec spec = parse_campaign(text, opt.spec_path, opt.max_replicas);
    if (opt.dry_run) {
        if (rank == 0) {
            if (extend)
                std::printf("(%s holds this campaign with shorter runs: the run would extend it, each "
                            "replica continuing from its final checkpoint)\n", output.c_str());
            if (grow)
                std::printf("(%s holds this campaign with fewer replicas: the run would grow it, keeping "
                            "%lld replicas and running %lld new ones)\n", output.c_str(),
                            static_cast<long long>(grow_kept),
                            static_cast<long long>(spec.replicas.size()) - static_cast<long long>(grow_kept));
            print_dry_run(spec, output, opt.plan);
        }
        return 0;
    }
    // One writer per archive: from here on this run holds it (refused while another lives).
    std::optional<ArchiveLock> lock;
    try {
        lock.emplace(ArchiveLock::acquire(comm, output, "jamsim run " + opt.spec_path));
        lock->hold_archive(output);
    } catch (const ArchiveBusy& e) {
        if (rank == 0) std::fprintf(stderr, "jamsim run: %s\n", e.what());
        return 2;
    }
    try {
        if (extend) {
            if (rank == 0)
                std::printf("extending %s to the longer runs of %s: finished replicas continue from "
                            "their final checkpoints%s\n", output.c_str(), opt.spec_path.c_str(),
                            spec.predecessor.empty() ? ""
                                                     : "; a rate ladder's later replicas run again from their "
                                                       "predecessors' new end states");
            Archive::extend(comm, output, spec);
            lock->hold_archive(output);  // the file was replaced
        }
        if (grow) {
            if (rank == 0)
                std::printf("growing archive %s: %lld replicas kept, %lld new\n", output.c_str(),
                            static_cast<long long>(grow_kept),
                            static_cast<long long>(spec.replicas.size()) - static_cast<long long>(grow_kept));
            Archive::grow(comm, output, spec, grow_source);
            lock->hold_archive(output);
        }
        int exists = rank == 0 ? std::filesystem::exists(output) : 0;
        mpi::broadcast(exists, 0, comm);
        std::optional<Archive> created;
        if (!exists) {
            // A creation that fails (a filesystem filled since the check) leaves no partial
            // file behind and says why in words, on every rank together (it is collective).
            std::string why;
            try {
                created.emplace(Archive::create(comm, output, spec));
            } catch (const h5::Error& e) {
                why = e.what();
            }
            int failed = !why.empty(), any = 0;
            mpi::check(MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, comm), "MPI_Allreduce");
            if (any) {
                created.reset();
                if (rank == 0) {
                    std::error_code ignored;
                    std::filesystem::remove(output, ignored);
                    std::fprintf(stderr, "jamsim run: %s: creating the archive '%s' failed%s; nothing was kept (%s)\n",
                                 opt.spec_path.c_str(), output.c_str(),
                                 disk_full(output) ? ": no space left on device" : "", why.c_str());
                }
                lock->release();
                return 2;
            }
        }
        Archive archive = exists ? Archive::open(comm, output) : std::move(*created);
        if (!exists) lock->hold_archive(output);
        archive.stamp("run_started");
        std::optional<InitialStates> initial;
        if (!spec.replicas.front().initial.empty()) initial.emplace(spec.replicas.front().initial);
        const FarmOptions farm{.progress = {redraw_progress(opt.progress), opt.progress_interval},
                               .shard = parse_shard(opt.shard),
                               .retry_failed = opt.retry_failed,
                               .archive_path = output,
                               .checkpoint_seconds = opt.checkpoint_seconds,
                               .initial_states = initial ? &*initial : nullptr};
        if (rank == 0)
            std::printf("campaign %s: %zu replicas on %d ranks -> %s%s\n", spec.name.c_str(),
                        spec.replicas.size(), mpi::size(comm), output.c_str(),
                        !exists            ? ""
                        : opt.retry_failed ? " (resuming: done replicas are skipped, failed ones run again)"
                                           : " (resuming: finished replicas are skipped)");
        const FarmSummary s = run_farm(comm, spec, archive, farm);
        double io = 0, wall = 0, local_io = s.io_seconds, local_wall = s.wall_seconds;
        // Interrupted (a signal, or a replica stopped at a checkpoint step) on any rank?
        int stopped = 0, local_stopped = StopRequest::requested() || s.interrupted > 0;
        mpi::check(MPI_Allreduce(&local_stopped, &stopped, 1, MPI_INT, MPI_MAX, comm), "MPI_Allreduce");
        long long interrupted = 0, local_interrupted = s.interrupted;
        mpi::check(MPI_Reduce(&local_interrupted, &interrupted, 1, MPI_LONG_LONG, MPI_SUM, 0, comm),
                   "MPI_Reduce");
        if (stopped) {
            archive.close();
            lock->release();
            if (rank == 0)
                std::printf("campaign %s interrupted after %.3f s: %lld running replicas saved their "
                            "state at a checkpoint step; run the same command again to continue\n",
                            spec.name.c_str(), s.wall_seconds, interrupted);
            return kExitInterrupted;
        }
        archive.stamp("run_finished");
        archive.close();
        lock->release();
        if (rank == 0) {  // the checkpoint folder, once every replica has removed its own
            std::error_code ignored;
            std::filesystem::remove(checkpoint_folder(output), ignored);  // only if empty
        }
        long long resumed = 0, local_resumed = s.resumed;
        mpi::check(MPI_Reduce(&local_resumed, &resumed, 1, MPI_LONG_LONG, MPI_SUM, 0, comm), "MPI_Reduce");
        long long ran = 0, local_ran = s.ran;
        mpi::check(MPI_Reduce(&local_ran, &ran, 1, MPI_LONG_LONG, MPI_SUM, 0, comm), "MPI_Reduce");
        long long failed = 0, local_failed = s.failed;
        mpi::check(MPI_Reduce(&local_io, &io, 1, MPI_DOUBLE, MPI_SUM, 0, comm), "MPI_Reduce");
        mpi::check(MPI_Reduce(&local_wall, &wall, 1, MPI_DOUBLE, MPI_SUM, 0, comm), "MPI_Reduce");
        mpi::check(MPI_Reduce(&local_failed, &failed, 1, MPI_LONG_LONG, MPI_SUM, 0, comm),
                   "MPI_Reduce");
        if (rank == 0) {
            std::printf("campaign %s finished in %.3f s: archive %s (%lld failed replicas; %lld "
                        "continued from checkpoints; archive writes took %.2f%% of rank time)\n",
                        spec.name.c_str(), s.wall_seconds, output.c_str(), failed, resumed,
                        wall > 0 ? 100.0 * io / wall : 0.0);
            std::printf("%lld replicas ran in this run, %lld finished before were kept\n", ran,
                        static_cast<long long>(s.skipped));
            std::printf("inspect with: jamsim status %s\n", output.c_str());
        }
    } catch (const std::exception& e) {
        // One rank cannot leave the others waiting in a collective call: abort the job.
        if (dynamic_cast<const h5::Error*>(&e) && disk_full(output))
            std::fprintf(stderr, "jamsim run (rank %d): no space left on device: writing the archive '%s' "
                                 "failed (%s); the replicas finished before are safe in it (jamsim status "
                                 "%s): free space and run the same command again to continue\n",
                         rank, output.c_str(), e.what(), output.c_str());
        else
            std::fprintf(stderr, "jamsim run (rank %d): error: %s\n", rank, e.what());
        MPI_Abort(comm, 1);
    }
    return 0;
}

/// A bad file given as an archive: its diagnosis on stderr, exit status 2.
constexpr int kExitRefused = 2;

int status(const std::string& path) {
    if (const std::string bad = diagnose_archive_file(path); !bad.empty()) {
        std::fprintf(stderr, "jamsim status: %s\n", bad.c_str());
        return kExitRefused;
    }
    const ArchiveSummary s = summarize_archive(path);
    const long long total = s.pending + s.running + s.done + s.failed;
    std::printf("campaign %s (%s): %lld/%lld done, %lld running, %lld failed, %lld pending\n",
                s.campaign.c_str(), path.c_str(), static_cast<long long>(s.done), total,
                static_cast<long long>(s.running), static_cast<long long>(s.failed),
                static_cast<long long>(s.pending));
    // Complete: every replica done or failed, whether by runs or by merging shards (a merged
    // archive has no run of its own that finished).
    const bool complete = s.pending == 0 && s.running == 0;
    const bool run_finished = !s.finished.empty() && !(s.finished < s.started);
    std::string state = complete        ? "complete: every replica is finished"
                        : run_finished ? ""
                                       : "running or interrupted";
    if (complete && !s.merged.empty()) state += "; merged " + s.merged;
    std::printf("last run started %s, finished %s%s\n", s.started.empty() ? "-" : s.started.c_str(),
                run_finished ? s.finished.c_str() : "-",
                state.empty() ? "" : (" (" + state + ")").c_str());
    if (s.cost_done > 0 && s.cost_left > 0) {
        const double per_cost = s.wall_seconds_done / s.cost_done;
        const double ranks = s.ranks > 0 ? static_cast<double>(s.ranks) : 1.0;
        std::printf("remaining: about %.0f s on %lld ranks (%.0f core-seconds)\n",
                    per_cost * s.cost_left / ranks, static_cast<long long>(ranks),
                    per_cost * s.cost_left);
    }
    for (const auto& r : s.in_progress)
        std::printf("running or interrupted replica %lld: %.1f%% of its steps at its last checkpoint\n",
                    static_cast<long long>(r.replica), 100.0 * r.fraction);
    for (const auto& f : s.failures) std::printf("failed %s\n", f.c_str());
    return 0;
}

/// "N = 64, phi = 0.84, rate = 0.003, seed = 2": a replica for a person (sweep parameters).
std::string replica_label(const ReplicaParams& p) {
    return "N = " + std::to_string(p.n) + ", phi = " + show_value(p.phi) + ", rate = " + show_value(p.rate) +
           ", seed = " + std::to_string(p.seed);
}

/// Shards of one campaign, or archives of campaigns that differ only in their sweeps: the
/// output's campaign is then the union of their replicas (matched by identity: parameters and
/// seed), as a campaign file of points with their own seeds (campaign_text).
int merge(const std::string& output, const std::vector<std::string>& inputs, int& argc,
          char**& argv) {
    mpi::Session session(argc, argv);
    if (mpi::size(MPI_COMM_WORLD) != 1) {
        std::fprintf(stderr, "jamsim merge: run it as one process (no mpirun -n > 1)\n");
        return 2;
    }
    std::vector<StoredCampaign> stored;
    for (const auto& path : inputs) {
        if (path == output) {
            std::fprintf(stderr, "jamsim merge: '%s' is both the output and an input: name a new output\n",
                         path.c_str());
            return 2;
        }
        if (const std::string bad = diagnose_archive_file(path); !bad.empty()) {
            std::fprintf(stderr, "jamsim merge: shard %s\n", bad.c_str());
            return kExitRefused;
        }
        try {
            stored.push_back(read_stored_campaign(path));
        } catch (const std::exception& e) {
            std::fprintf(stderr, "jamsim merge: shard '%s': %s\n", path.c_str(), e.what());
            return 2;
        }
        // The stored fingerprint must be this version's: a shard written by a version whose
        // results mean something else (an older fingerprint) is not merged with new ones.
        if (const std::string why = Archive::check_existing(path, stored.back().spec); !why.empty()) {
            std::fprintf(stderr, "jamsim merge: shard '%s': %s\n", path.c_str(), why.c_str());
            return 2;
        }
        // Campaigns may differ in their sweeps, in nothing else.
        if (const std::string differs = settings_difference(stored.front().spec, stored.back().spec,
                                                            "'" + inputs.front() + "'", "'" + path + "'");
            !differs.empty()) {
            std::fprintf(stderr, "jamsim merge: '%s' belongs to a different campaign than '%s': %s "
                         "(archives merge when they differ only in their sweeps)\n",
                         path.c_str(), inputs.front().c_str(), differs.c_str());
            return 2;
        }
    }
    // The union of the replicas, each once (by its identity: its fingerprint line).
    std::map<std::string, std::size_t> in_union;
    std::vector<ReplicaParams> all;
    for (const auto& s : stored)
        for (const ReplicaParams& p : s.spec.replicas)
            if (in_union.emplace(describe(p), all.size()).second) all.push_back(p);
    // An input's own campaign when it holds them all (shards of one campaign), else one written
    // for the union.
    std::optional<CampaignSpec> merged;
    for (const auto& s : stored) {
        std::set<std::string> own;
        for (const ReplicaParams& p : s.spec.replicas) own.insert(describe(p));
        if (own.size() == all.size() && s.spec.replicas.size() == all.size()) {
            merged = s.spec;
            break;
        }
    }
    if (!merged) {
        std::string from;
        for (const auto& path : inputs) from += (from.empty() ? "" : ", ") + path;
        try {
            merged = parse_campaign(campaign_text(stored.front().spec.name, output, all,
                                                  "The campaign of jamsim merge " + from +
                                                      ":\nthe union of their replicas, points with their own seeds."),
                                    output + " (merged campaign)", std::numeric_limits<std::int64_t>::max());
        } catch (const SpecError& e) {
            std::fprintf(stderr, "jamsim merge: cannot describe the merged campaign: %s\n", e.what());
            return 2;
        }
        bool same = merged->replicas.size() == all.size();
        for (const ReplicaParams& p : merged->replicas) same = same && in_union.count(describe(p));
        if (!same) {
            std::fprintf(stderr, "jamsim merge: the merged campaign does not hold the replicas of its "
                                 "inputs (a rate ladder whose chains differ between them?): refusing\n");
            return 2;
        }
    }
    const CampaignSpec& spec = *merged;
    // Each input replica's id in the output: the same id for shards of the output's campaign.
    const std::string merged_fingerprint = fingerprint(spec);
    std::map<std::string, std::int64_t> position;
    for (std::size_t id = spec.replicas.size(); id-- > 0;)
        position[describe(spec.replicas[id])] = static_cast<std::int64_t>(id);
    std::vector<std::vector<std::int64_t>> target(stored.size());
    for (std::size_t k = 0; k < stored.size(); ++k) {
        const bool same_campaign = fingerprint(stored[k].spec) == merged_fingerprint;
        for (std::size_t r = 0; r < stored[k].spec.replicas.size(); ++r)
            target[k].push_back(same_campaign ? static_cast<std::int64_t>(r)
                                              : position.at(describe(stored[k].spec.replicas[r])));
    }
    // A replica finished in two inputs must be the same, bitwise.
    {
        std::map<std::int64_t, std::pair<std::size_t, std::size_t>> first_done;  // output id -> (input, id)
        for (std::size_t k = 0; k < stored.size(); ++k)
            for (std::size_t r = 0; r < stored[k].status.size(); ++r) {
                if (stored[k].status[r] != ReplicaStatus::Done) continue;
                const auto [it, fresh] = first_done.emplace(target[k][r], std::pair{k, r});
                if (fresh) continue;
                const auto [j, q] = it->second;
                std::string differs;
                try {
                    differs = Archive::replica_difference(inputs[j], static_cast<std::int64_t>(q), inputs[k],
                                                          static_cast<std::int64_t>(r));
                } catch (const std::exception& e) {
                    differs = std::string("cannot be compared: ") + e.what();
                }
                if (!differs.empty()) {
                    std::fprintf(stderr, "jamsim merge: the replica %s is in '%s' (replica %zu) and '%s' "
                                 "(replica %zu) with different data (%s): refusing to merge them\n",
                                 replica_label(stored[k].spec.replicas[r]).c_str(), inputs[j].c_str(), q,
                                 inputs[k].c_str(), r, differs.c_str());
                    return 2;
                }
            }
    }
    const bool exists = std::filesystem::exists(output);
    if (const std::string too_large = check_capacity(estimate_capacity(spec, output, 1, 1), {}, spec, output);
        !too_large.empty()) {
        std::fprintf(stderr, "jamsim merge: %s\n", too_large.c_str());
        return 2;
    }
    // The output is written by this process alone, and no input may still be written.
    std::optional<ArchiveLock> lock;
    try {
        for (const auto& path : inputs) ArchiveLock::check_free(path);
        lock.emplace(ArchiveLock::acquire(MPI_COMM_SELF, output, "jamsim merge"));
    } catch (const ArchiveBusy& e) {
        std::fprintf(stderr, "jamsim merge: %s\n", e.what());
        return 2;
    }
    if (exists) {
        if (const std::string bad = diagnose_archive_file(output); !bad.empty()) {
            std::fprintf(stderr, "jamsim merge: refusing the output: %s\n", bad.c_str());
            return kExitRefused;
        }
        const std::string why = Archive::check_existing(output, spec);
        if (!why.empty()) {
            std::fprintf(stderr, "jamsim merge: refusing: %s\n", why.c_str());
            return 2;
        }
    }
    Archive out = exists ? Archive::open(MPI_COMM_SELF, output)
                         : Archive::create(MPI_COMM_SELF, output, spec);
    std::vector<ReplicaStatus> have = out.read_status();
    long long copied = 0;
    for (std::size_t k = 0; k < inputs.size(); ++k)
        for (std::size_t r = 0; r < stored[k].status.size(); ++r) {
            const ReplicaStatus s = stored[k].status[r];
            const auto t = static_cast<std::size_t>(target[k][r]);
            const bool finished = s == ReplicaStatus::Done || s == ReplicaStatus::Failed;
            if (!finished || have[t] == ReplicaStatus::Done) continue;
            if (have[t] == ReplicaStatus::Failed && s == ReplicaStatus::Failed) continue;
            out.import_replica(inputs[k], static_cast<std::int64_t>(r), static_cast<std::int64_t>(t));
            have[t] = s;
            ++copied;
        }
    out.stamp("merged");
    out.close();
    lock->release();
    std::printf("merged %lld replicas from %zu archives into %s", copied, inputs.size(), output.c_str());
    if (merged_fingerprint != fingerprint(stored.front().spec))
        std::printf(" (a campaign of %zu replicas: the union of their sweeps)", spec.replicas.size());
    std::printf("\n");
    return status(output);
}

} // namespace

CLI::App* add_merge_command(CLI::App& app, int& argc, char**& argv) {
    auto output = std::make_shared<std::string>();
    auto shards = std::make_shared<std::vector<std::string>>();
    auto* cmd = app.add_subcommand(
        "merge", "Merge archives into one: shards of one campaign (jamsim run --shard K/N), or "
                 "campaigns that differ only in their sweeps (the output holds the union of their replicas)");
    cmd->add_option("-o,--output", *output,
                    "Merged archive (created, or completed if it exists); without -o the first "
                    "archive named is the output");
    cmd->add_option("archives", *shards, "[OUTPUT] then the archives to merge")->required();
    cmd->callback([output, shards, &argc, &argv] {
        int rc = 1;
        try {
            std::vector<std::string> inputs = *shards;
            std::string out = *output;
            if (out.empty()) {  // jamsim merge OUTPUT A.h5 B.h5 ...
                out = inputs.front();
                inputs.erase(inputs.begin());
            }
            if (inputs.empty()) {
                std::fprintf(stderr, "jamsim merge: no archives to merge (jamsim merge -o OUT A.h5 B.h5 ...)\n");
                rc = 2;
            } else {
                rc = merge(out, inputs, argc, argv);
            }
        } catch (const std::exception& e) {
            std::fprintf(stderr, "jamsim merge: %s\n", e.what());
        }
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
    return cmd;
}

CLI::App* add_run_command(CLI::App& app, int& argc, char**& argv) {
    auto opt = std::make_shared<RunOptions>();
    auto* cmd = app.add_subcommand("run", "Run a campaign over MPI ranks into one HDF5 archive");
    cmd->add_option("campaign", opt->spec_path, "Campaign file (TOML)")->required();
    cmd->add_option("-o,--output", opt->output, "Archive path (overrides [campaign] output)");
    cmd->add_flag("--dry-run", opt->dry_run, "List replicas and costs; write nothing");
    add_threads_option(*cmd);
    cmd->add_option_function<std::string>(
           "--progress-interval",
           [opt](const std::string& text) {
               // A negative or non-finite interval would print a line at every sample.
               char* end = nullptr;
               const double v = std::strtod(text.c_str(), &end);
               if (text.empty() || *end != '\0' || !std::isfinite(v) || v < 0)
                   throw CLI::ValidationError("jamsim run: --progress-interval = " + text +
                                              " is not allowed: a finite number of seconds >= 0");
               opt->progress_interval = v;
           },
           "Seconds between progress lines when not on a terminal")
        ->default_str("10");
    cmd->add_flag("--retry-failed", opt->retry_failed,
                  "Run the failed replicas of an existing archive again (after a fix to the code "
                  "or the machine; the campaign itself cannot change)");
    cmd->add_option_function<std::string>(
        "--checkpoint-every",
        [opt](const std::string& v) {
            opt->checkpoint_seconds = parse_duration(v);
            if (opt->checkpoint_seconds < 0)
                throw CLI::ValidationError("jamsim run: --checkpoint-every = " + v +
                                           " is not allowed: a duration >= 0 such as 300, 90s, 15min or 2h");
        },
        "Save each running replica's state at its first checkpoint step after this long "
        "(0: at every checkpoint step; [run] checkpoint_steps sets the steps)")
        ->default_str("300s");
    cmd->add_option("--max-replicas", opt->max_replicas,
                    "Refuse a campaign of more replicas (a typo in seeds or a sweep list)")
        ->check(CLI::Validator(
            [](std::string& v) -> std::string {
                char* end = nullptr;
                const long long n = std::strtoll(v.c_str(), &end, 10);
                return end != v.c_str() && *end == '\0' && n >= 1
                           ? ""
                           : "value " + v + " is not allowed: a whole number of replicas >= 1";
            },
            "COUNT >= 1"))
        ->capture_default_str();
    cmd->add_option_function<std::string>(
        "--max-archive-size",
        [opt](const std::string& v) {
            opt->limits.max_archive_bytes = parse_bytes(v);
            if (!(opt->limits.max_archive_bytes > 0))
                throw CLI::ValidationError("jamsim run: --max-archive-size = " + v +
                                           " is not allowed: a size > 0 such as 500G, 2T or 1e13");
        },
        "Refuse a campaign whose archive would be larger (the free space of its filesystem is "
        "checked as well)")
        ->default_str("1T");
    cmd->add_option("--ranks", opt->plan.ranks, "--dry-run: ranks of the planned run")
        ->check(CLI::PositiveNumber)->default_str("1");
    cmd->add_option("--shards", opt->plan.shards, "--dry-run: Slurm array tasks of the planned run")
        ->check(CLI::PositiveNumber)->default_str("1");
    cmd->add_option_function<std::string>(
        "--time-limit",
        [opt](const std::string& v) {
            opt->plan.time_limit = parse_duration(v);
            if (!(opt->plan.time_limit > 0))
                throw CLI::ValidationError("jamsim run: --time-limit = " + v +
                                           " is not allowed: a duration > 0 such as 3600, 90min or 24h");
        },
        "--dry-run: a task's time limit, to count the requeues it needs");
    cmd->add_flag("!--no-calibrate", opt->plan.calibrate,
                  "--dry-run: nominal throughput instead of a short probe per model and N");
    cmd->add_option("--shard", opt->shard,
                    "K/N: run only replicas with id % N == K (merge shards with jamsim merge)");
    cmd->add_option("--progress", opt->progress,
                    "auto (redraw on a terminal), lines (log files) or redraw")
        ->check(CLI::IsMember({"auto", "lines", "redraw"}))
        ->capture_default_str();
    cmd->callback([opt, &argc, &argv] {
        parse_shard(opt->shard);  // bad value: message and exit before MPI starts
        const int rc = run(*opt, argc, argv);
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
    return cmd;
}

CLI::App* add_status_command(CLI::App& app) {
    auto path = std::make_shared<std::string>();
    auto* cmd = app.add_subcommand("status", "Summarise a campaign archive (also while running)");
    cmd->add_option("archive", *path, "Campaign archive (HDF5)")->required();
    cmd->callback([path] {
        int rc = 1;
        try {
            rc = status(*path);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "jamsim status: %s\n", e.what());
        }
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
    return cmd;
}

} // namespace jamsim::app
