// `jamsim plan`: a campaign's wall time on machines this one is not, by the farm's scheduler
// simulated (plan_command.hpp).
#include "plan_command.hpp"
#include "option_checks.hpp"
#include "dry_run.hpp"
#include "threads_option.hpp"
#include "wall_time.hpp"
#include "jamsim/core/parse_number.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <cstring>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "jamsim/archive/archive_file_check.hpp"
#include "jamsim/campaign/scheduler.hpp"
#include "jamsim/params/parameters.hpp"
#include "jamsim/spec/campaign_spec.hpp"
#include "jamsim/linalg/contact_solver.hpp"
#include "jamsim/parallel/mpi.hpp"

namespace jamsim::app {

namespace {

struct PlanOptions {
    std::string spec_path;
    std::string costs;   ///< a dry run's listing to take the seconds from ("": estimate them)
    std::string output;  ///< the archive whose finished replicas calibrate ("": the campaign's)
    std::vector<int> nodes{1, 4, 16, 64};
    std::vector<int> threads{1};
    int cores_per_node = 64;
    DryRunPlan estimate;
};

/// A refused input: one message naming the file, the value and what is allowed.
struct PlanError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Each replica's seconds and sampling seconds from the listing of `jamsim run --dry-run` (the
/// rows "id N phi rate seed samples cost est.s sampling"): every replica of `spec` once, with
/// its N.
ReplicaSeconds seconds_from_listing(const std::string& path, const CampaignSpec& spec) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw PlanError("jamsim plan: --costs " + path + ": is a directory, not the listing of a dry run");
    if (const std::string odd = not_a_regular_file(path); !odd.empty())
        throw PlanError("jamsim plan: --costs " + path + ": " + odd + " (the listing of a dry run)");
    std::ifstream in(path);
    if (!in)
        throw PlanError("jamsim plan: --costs " + path + ": cannot be read (" + std::strerror(errno) +
                        "; the listing of a dry run)");
    // id N phi rate seed samples cost est.s sampling
    static const std::regex row(R"(^\s*(\d+)\s+(\d+)\s+(\S+)\s+(\S+)\s+(\d+)\s+\d+\s+\S+\s+(\S+)\s+(\S+)\s*$)");
    std::vector<double> seconds(spec.replicas.size(), -1.0), serial(spec.replicas.size(), 0.0);
    std::size_t found = 0;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        std::smatch m;
        if (!std::regex_match(line, m, row)) continue;
        const std::string where =
            "jamsim plan: --costs " + path + ":" + std::to_string(number) + ": replica " + m[1].str();
        std::size_t id = 0;
        long long n = 0;
        double listed_seconds = 0.0, listed_serial = 0.0;
        if (!parse_whole_text(m[1].str(), id) || !parse_whole_text(m[2].str(), n) ||
            !parse_finite(m[6].str(), listed_seconds) || !parse_finite(m[7].str(), listed_serial))
            throw PlanError(where + ": '" + line +
                            "' is not allowed: a row of the dry run's listing (id and N "
                            "whole numbers, est.s and sampling finite numbers of seconds)");
        // The replica's N, phi, rate and seed as the dry run prints them: phi and rate as the
        // shortest text that reads back the same (show_value), or as listings before it did
        // (phi to 4 digits, rate to 3; such a listing of phi = 0.84012 was refused).
        const auto listed_as = [](const char* format, double value, const std::string& text) {
            char old[32];
            std::snprintf(old, sizeof old, format, value);
            return text == show_value(value) || text == old;
        };
        if (id >= spec.replicas.size() || spec.replicas[id].n != n ||
            !listed_as("%.4g", spec.replicas[id].phi, m[3].str()) ||
            !listed_as("%.3g", spec.replicas[id].rate, m[4].str()) ||
            std::to_string(spec.replicas[id].seed) != m[5].str())
            throw PlanError(where + " (N = " + m[2].str() + ", phi = " + m[3].str() + ", rate = " + m[4].str() +
                            ", seed = " + m[5].str() + ") is not replica " + m[1].str() + " of " + spec.path +
                            ": give the listing of `jamsim run --dry-run " + spec.path + "`");
        if (seconds[id] >= 0) throw PlanError(where + " is listed twice");
        seconds[id] = listed_seconds;
        serial[id] = listed_serial;
        if (!(seconds[id] >= 0 && serial[id] >= 0 && serial[id] <= seconds[id] && seconds[id] <= 1e12))
            throw PlanError(where + ": est.s = " + m[6].str() + ", sampling = " + m[7].str() +
                            " are not allowed: seconds from 0 to 1e12, the sampling's part of them at most all of "
                            "them");
        ++found;
    }
    if (found != spec.replicas.size()) {
        const auto missing = std::find_if(seconds.begin(), seconds.end(), [](double v) { return v < 0; });
        throw PlanError("jamsim plan: --costs " + path + " lists " + std::to_string(found) + " of the " +
                        std::to_string(spec.replicas.size()) + " replicas of " + spec.path + " (not replica " +
                        std::to_string(missing - seconds.begin()) +
                        "): give the whole listing of `jamsim run --dry-run " + spec.path + "`");
    }
    return {.seconds = seconds, .serial = serial, .source = "one-thread seconds from " + path, .extrapolated = {}};
}

int plan(const PlanOptions& opt, int& argc, char**& argv) {
    mpi::Session session(argc, argv);
    const linalg::PetscScope petsc;  // a probe of CD0 solves with PETSc
    if (mpi::rank(MPI_COMM_WORLD) != 0) return 0;
    // The simulation keeps a state per rank and steps through every start: 2^20 cores (16384
    // nodes of 64) take about a second; 10^11 ran for minutes or ended in std::bad_alloc.
    constexpr long long kMostCores = 1LL << 20;
    for (const int k : opt.nodes)
        if (static_cast<long long>(k) * opt.cores_per_node > kMostCores)
            throw PlanError("jamsim plan: --nodes " + std::to_string(k) + " is not allowed with --cores-per-node " +
                            std::to_string(opt.cores_per_node) + ": at most " + std::to_string(kMostCores) +
                            " cores in all (nodes x cores per node) are simulated");
    for (const int t : opt.threads)
        if (opt.cores_per_node % t != 0)
            throw PlanError("jamsim plan: --threads " + std::to_string(t) + " is not allowed with --cores-per-node " +
                            std::to_string(opt.cores_per_node) + ": a divisor of the cores per node");
    const CampaignSpec spec = load_campaign(opt.spec_path, kDefaultMaxReplicas, 1);
    ReplicaSeconds estimate;
    if (!opt.costs.empty()) {
        estimate = seconds_from_listing(opt.costs, spec);
    } else {
        // An archive that exists but cannot be read gives no recorded rates: say so.
        const std::string archive = opt.output.empty() ? spec.output : opt.output;
        std::error_code ec;
        if (opt.estimate.calibrate && std::filesystem::exists(archive, ec))
            if (const std::string bad = diagnose_archive_file(archive); !bad.empty())
                std::fprintf(stderr, "jamsim plan: warning: no recorded rates are taken from the archive: %s\n",
                             bad.c_str());
        estimate = replica_seconds(spec, opt.output.empty() ? spec.output : opt.output, opt.estimate.calibrate,
                                   opt.estimate.probe_seconds);
    }
    const Chains chains = chains_of(spec.predecessor, spec.replicas.size());
    const SpeedupModel model{.serial_fraction = opt.estimate.serial_fraction};
    double work = 0;
    for (const double s : estimate.seconds) work += s;
    const SimulatedRun serial = simulate_schedule(simulated_replicas(spec, estimate.seconds, estimate.serial, 1, model),
                                                  spec.predecessor, 1, 1);
    std::printf("campaign %s: %s in %s, %.4g core-hours on one thread (%s)\n", spec.name.c_str(),
                counted(static_cast<long long>(spec.replicas.size()), "replica").c_str(),
                counted(static_cast<long long>(chains.members.size()), "chain").c_str(), work / 3600,
                estimate.source.c_str());
    if (serial.longest_chain >= 0)
        std::printf("longest chain on one thread: %s, %s\n", duration(serial.critical_path).c_str(),
                    describe_chain(spec, chains, serial.longest_chain).c_str());
    std::printf("speed-up on threads: %s\n", describe_speedup(model).c_str());
    std::printf("the farm's scheduler (longest remaining chain first) simulated on nodes of %d cores, each rank "
                "running one replica at a time on its threads; bound = max(work / cores, critical path); idle: "
                "cores without a replica; efficiency: one-thread work / (cores x makespan); lent: the makespan "
                "when ranks without work lend their cores to the running replicas of their node (ranks started "
                "unbound: README \"Cores lent by ranks without work\"):\n\n",
                opt.cores_per_node);
    std::printf("| nodes | ranks × threads | makespan | bound | critical path | cores idle (mean) | idle | "
                "efficiency | lent: makespan, idle |\n");
    std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const int k : opt.nodes)
        for (const int t : opt.threads) {
            const int ranks = k * opt.cores_per_node / t;
            const auto replicas = simulated_replicas(spec, estimate.seconds, estimate.serial, t, model);
            const SimulatedRun run = simulate_schedule(replicas, spec.predecessor, ranks, t);
            const SimulatedLending lending{.ranks_per_node = opt.cores_per_node / t, .model = model};
            const SimulatedRun lent = simulate_schedule(replicas, spec.predecessor, ranks, t, &lending);
            const double cores = static_cast<double>(ranks) * t;
            const double core_time = std::max(1e-300, cores * run.makespan);
            std::printf("| %d | %d × %d | %s | %s | %s | %.1f of %.0f | %.0f%% | %.0f%% | %s, %.0f%% |\n", k, ranks, t,
                        duration(run.makespan).c_str(), duration(run.bound).c_str(),
                        duration(run.critical_path).c_str(), run.idle_core_seconds / std::max(1e-300, run.makespan),
                        cores, 100 * run.idle_core_seconds / core_time, 100 * run.work / core_time,
                        duration(lent.makespan).c_str(),
                        100 * lent.idle_core_seconds / std::max(1e-300, cores * lent.makespan));
        }
    return 0;
}

/// A comma-separated list of whole numbers >= 1 ("1,4,16"), or an exception naming it.
std::vector<int> positive_list(const std::string& option, const std::string& text) {
    std::vector<int> out;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');) {
        char* end = nullptr;
        const long v = std::strtol(item.c_str(), &end, 10);
        if (item.empty() || *end != '\0' || v < 1 || v > 1'000'000)
            throw CLI::ValidationError("jamsim plan: " + option + " = " + text +
                                       " is not allowed: whole numbers >= 1, separated by commas (e.g. 1,4,16)");
        // A repeated value would print its row twice: keep the first.
        if (std::find(out.begin(), out.end(), static_cast<int>(v)) == out.end()) out.push_back(static_cast<int>(v));
    }
    if (out.empty())
        throw CLI::ValidationError("jamsim plan: " + option + " = \"\" is not allowed: whole numbers >= 1");
    return out;
}

}  // namespace

CLI::App* add_plan_command(CLI::App& app, int& argc, char**& argv) {
    auto opt = std::make_shared<PlanOptions>();
    auto* cmd = app.add_subcommand(
        "plan", "A campaign's wall time on K nodes of C cores (the farm's scheduler simulated on the dry run's "
                "per-replica costs): makespan, its bound, cores left idle");
    cmd->add_option("campaign", opt->spec_path, "Campaign file (TOML)")->required()->type_name("FILE");
    cmd->add_option_function<std::string>(
           "--nodes", [opt](const std::string& v) { opt->nodes = positive_list("--nodes", v); },
           "Node counts, comma-separated")
        ->default_str("1,4,16,64")
        ->type_name("LIST");
    cmd->add_option("--cores-per-node", opt->cores_per_node, "Cores of each node")
        ->check(count_from_one_to("cores", 1'000'000))
        ->capture_default_str();
    cmd->add_option_function<std::string>(
           "--threads", [opt](const std::string& v) { opt->threads = positive_list("--threads", v); },
           "Threads per rank (each a divisor of the cores per node), comma-separated")
        ->default_str("1")
        ->type_name("LIST");
    cmd->add_option("--costs", opt->costs,
                    "The output of `jamsim run --dry-run CAMPAIGN` saved to a file: its per-replica seconds, "
                    "instead of probing again")
        ->type_name("FILE");
    cmd->add_option("-o,--output", opt->output, "The archive whose finished replicas calibrate the throughput")
        ->check(nonempty_path())
        ->type_name("FILE");
    cmd->add_flag_callback(
        "--no-calibrate", [opt] { opt->estimate.calibrate = false; },
        "Nominal throughput instead of a short probe per model and N");
    add_serial_fraction_option(*cmd, opt->estimate.serial_fraction);
    add_probe_seconds_option(*cmd, opt->estimate.probe_seconds);
    cmd->callback([opt, cmd, &argc, &argv] {
        // An option that another makes unused would be silently dropped.
        const auto refuse_with = [cmd](const char* given, const char* name, const char* why) {
            if (cmd->count(given) > 0 && cmd->count(name) > 0)
                throw CLI::ValidationError(std::string("jamsim plan: ") + name + " is not allowed with " + given +
                                           ": " + why);
        };
        for (const char* name : {"--output", "--no-calibrate", "--probe-seconds"})
            refuse_with("--costs", name,
                        "the listing's seconds are the costs (no archive is read and nothing is probed)");
        for (const char* name : {"--output", "--probe-seconds"})
            refuse_with("--no-calibrate", name, "nominal throughput reads no archive's rates and probes nothing");
        check_threads_environment("jamsim plan", false);  // its probes run the kernel
        int rc = 2;
        try {
            rc = plan(*opt, argc, argv);
        } catch (const PlanError& e) { std::fprintf(stderr, "%s\n", e.what()); } catch (const SpecError& e) {
            std::fprintf(stderr, "jamsim plan: %s\n", e.what());
        }
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
    return cmd;
}

}  // namespace jamsim::app
