#include "campaign_commands.hpp"
#include "option_checks.hpp"
#include "dry_run.hpp"
#include "exit_status.hpp"
#include "threads_option.hpp"
#include "wall_time.hpp"

#include <charconv>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <cstdlib>
#include <memory>
#include <sstream>

#include "jamsim/archive/capacity.hpp"
#include "jamsim/io/hdf5.hpp"
#include "jamsim/campaign/lifecycle.hpp"
#include "jamsim/campaign/scheduler.hpp"
#include "jamsim/linalg/contact_solver.hpp"
#include "jamsim/parallel/mpi.hpp"
#include "jamsim/parallel/threads.hpp"

namespace jamsim::app {

namespace {

struct RunOptions {
    std::string spec_path;
    std::string output;  // overrides [campaign] output
    bool dry_run = false;
    double progress_interval = 10.0;
    std::string progress = "auto";    // auto | lines | redraw
    std::string shard;                // "K/N" or empty
    std::string time_limit_text;      // --time-limit as written, for its refusal
    bool retry_failed = false;        // run failed replicas again
    double checkpoint_seconds = 300;  // save a running replica's state at most this often
    DryRunPlan plan;                  // what --dry-run estimates for
    std::int64_t max_replicas = kDefaultMaxReplicas;
    CapacityLimits limits;
};

/// The longest duration an option takes (about 32 years): longer ones are typos.
constexpr double kLongestDuration = 1e9;

/// "90", "90s", "15min", "2h" in seconds (decimal, at most kLongestDuration); negative when it
/// does not parse.
double parse_duration(const std::string& text) {
    double v = 0.0;  // decimal only (strtod read 0x1000 as 4096 s)
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    const std::string unit(end, text.data() + text.size());
    const double scale = unit.empty() || unit == "s" ? 1.0 : unit == "min" ? 60.0 : unit == "h" ? 3600.0 : -1.0;
    if (ec != std::errc{} || scale < 0 || !(v >= 0)) return -1.0;
    const double seconds = v * scale;  // 1e306h overflowed to an infinite limit
    return seconds <= kLongestDuration ? seconds : -1.0;
}

/// "K/N" with 0 <= K < N, or an exception naming the value.
Shard parse_shard(const std::string& text) {
    Shard s;
    char slash = 0;
    std::istringstream in(text);
    if (text.empty()) return s;
    if (!(in >> s.index >> slash >> s.count) || slash != '/' || !in.eof() || s.count < 1 || s.index < 0 ||
        s.index >= s.count)
        throw CLI::ValidationError("jamsim run: --shard = " + text +
                                   " is not allowed: K/N with 0 <= K < N (e.g. 3/16)");
    return s;
}

/// Under mpirun a rank's stdout is a pseudo-terminal even when the job's output goes to a
/// file, so `auto` redraws only for a single process on a terminal outside batch jobs and CI;
/// `--progress redraw` asks for it explicitly.
bool redraw_progress(const std::string& mode) {
    if (mode != "auto") return mode == "redraw";
    return isatty(STDOUT_FILENO) != 0 && !std::getenv("OMPI_COMM_WORLD_SIZE") && !std::getenv("PMI_RANK") &&
           !std::getenv("SLURM_JOB_ID") && !std::getenv("CI");
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

/// Rank 0's findings, as the dry run or the run reports them before any work.
void print_decision(const RunDecision& d) {
    for (const std::string& note : d.notes) std::printf("jamsim run: %s\n", note.c_str());
    for (const std::string& warning : d.warnings) std::fprintf(stderr, "jamsim run: warning: %s\n", warning.c_str());
}

/// The dry run's listing (rank 0): what the run would do with the archive, then the plan.
void print_dry_run_of(const CampaignSpec& spec, const RunDecision& d, const DryRunPlan& plan) {
    const auto added = static_cast<long long>(spec.replicas.size()) - static_cast<long long>(d.grow_kept);
    if (d.mode == OutputMode::Extend)
        std::printf("(%s holds this campaign with shorter runs: the run would extend it, each "
                    "replica continuing from its final checkpoint)\n",
                    d.output.c_str());
    if (d.mode == OutputMode::Grow)
        std::printf("(%s holds this campaign with fewer replicas: the run would grow it, keeping "
                    "%lld replicas and running %lld new ones)\n",
                    d.output.c_str(), static_cast<long long>(d.grow_kept), added);
    print_dry_run(spec, d.output, plan);
}

/// The run's closing lines (rank 0).
int print_outcome(const CampaignSpec& spec, const RunDecision& d, const RunOutcome& o) {
    if (o.end == RunOutcome::End::refused) {
        std::fprintf(stderr, "jamsim run: %s\n", o.refusal.c_str());
        return kExitRefused;
    }
    if (o.end == RunOutcome::End::interrupted) {
        std::printf("campaign %s interrupted after %.3f s: %lld running replicas saved their "
                    "state at a checkpoint step; run the same command again to continue\n",
                    spec.name.c_str(), o.wall_seconds, static_cast<long long>(o.interrupted));
        return kExitInterrupted;
    }
    std::printf("campaign %s finished in %.3f s: archive %s (%lld failed replicas; %lld "
                "continued from checkpoints; archive writes took %.2f%% of rank time)\n",
                spec.name.c_str(), o.wall_seconds, d.output.c_str(), static_cast<long long>(o.failed),
                static_cast<long long>(o.resumed), 100.0 * o.io_share);
    std::printf("%s ran in this run, %lld finished before were kept\n",
                counted(static_cast<long long>(o.ran), "replica").c_str(), static_cast<long long>(o.skipped));
    std::printf("inspect with: jamsim status %s\n", d.output.c_str());
    // Failures of earlier runs too: a rerun that skipped a failed replica said "0 failed".
    try {
        if (const ArchiveSummary held = summarize_archive(d.output); held.failed > 0)
            std::fprintf(stderr,
                         "jamsim run: warning: %s of the archive failed (jamsim status %s gives the reasons); "
                         "after a fix, --retry-failed runs them again\n",
                         counted(held.failed, "replica").c_str(), d.output.c_str());
    } catch (const std::exception&) {}  // only a note: the run itself is done
    return 0;
}

/// Rank 0's decision on every rank.
void broadcast(RunDecision& d, MPI_Comm comm) {
    int mode = static_cast<int>(d.mode);
    mpi::broadcast(d.error, 0, comm);
    mpi::broadcast(d.spec_text, 0, comm);
    mpi::broadcast(d.output, 0, comm);
    mpi::broadcast(mode, 0, comm);
    d.mode = static_cast<OutputMode>(mode);
}

int run(const RunOptions& opt, int& argc, char**& argv) {
    // The stop signals' handler is installed first thing in main (main.cpp); PETSc is started
    // with -no_signal_handler, and MPI_Init leaves these signals alone.
    mpi::Session session(argc, argv);
    const linalg::PetscScope petsc;  // finalised before MPI (declared after the session)
    const MPI_Comm comm = MPI_COMM_WORLD;
    const int rank = mpi::rank(comm);
    if (!opt.dry_run)  // a note when --threads overrides OMP_NUM_THREADS; more threads than cores
        if (const std::string notes = threads_notes("jamsim run", comm); rank == 0) std::fputs(notes.c_str(), stderr);
    // Rank 0 reads and checks everything before any rank starts work.
    const int node_ranks = opt.dry_run ? opt.plan.ranks : mpi::ranks_on_node(comm);  // collective
    RunDecision decision;
    if (rank == 0) {
        decision = check_run({.spec_path = opt.spec_path,
                              .output = opt.output,
                              .dry_run = opt.dry_run,
                              .ranks = opt.dry_run ? opt.plan.ranks : mpi::size(comm),
                              .node_ranks = node_ranks,
                              .max_replicas = opt.max_replicas,
                              .limits = opt.limits});
        // A dry run's plan, sizes included, only once nothing refuses it (a refused --shards
        // came after the archive's line).
        if (!opt.dry_run || decision.error.empty()) print_decision(decision);
    }
    broadcast(decision, comm);
    if (!decision.error.empty()) {
        if (rank == 0) std::fprintf(stderr, "jamsim run: %s\n", decision.error.c_str());
        return kExitRefused;
    }
    const CampaignSpec spec = parse_campaign(decision.spec_text, opt.spec_path, opt.max_replicas);
    if (opt.dry_run) {
        // A shard past the chains holds none (a rate ladder's replicas stay together): the
        // listing would be one line per empty shard.
        const std::size_t chains = chains_of(spec.predecessor, spec.replicas.size()).members.size();
        if (static_cast<std::size_t>(opt.plan.shards) > chains) {
            if (rank == 0)
                std::fprintf(stderr, "jamsim run: --shards = %d is not allowed for %s: at most the campaign's %s\n",
                             opt.plan.shards, opt.spec_path.c_str(),
                             chains < spec.replicas.size()
                                 ? (std::to_string(chains) + " rate-ladder chains (each whole in one shard)").c_str()
                                 : counted(static_cast<long long>(chains), "replica").c_str());
            return kExitRefused;
        }
        if (rank == 0) {
            if (decision.sized) print_capacity(decision.capacity, decision.output);
            if (!decision.dry_run_refusal.empty())
                std::printf("the run would be refused: %s\n", decision.dry_run_refusal.c_str());
            print_dry_run_of(spec, decision, opt.plan);
        }
        return 0;
    }
    const RunSettings settings{.spec_path = opt.spec_path,
                               .progress = {redraw_progress(opt.progress), opt.progress_interval},
                               .shard = parse_shard(opt.shard),
                               .retry_failed = opt.retry_failed,
                               .checkpoint_seconds = opt.checkpoint_seconds,
                               .say = [](const std::string& line) { std::printf("%s\n", line.c_str()); }};
    try {
        const RunOutcome outcome = run_campaign(comm, spec, decision, settings);
        const int status = rank == 0 ? print_outcome(spec, decision, outcome) : 0;
        return outcome.end == RunOutcome::End::finished      ? status
               : outcome.end == RunOutcome::End::interrupted ? kExitInterrupted
                                                             : kExitRefused;
    } catch (const std::exception& e) {
        // One rank cannot leave the others waiting in a collective call: abort the job.
        // A refused write (a full disk, a quota, a failing device) in the system's words.
        const std::string refused = dynamic_cast<const h5::Error*>(&e) ? write_refused(decision.output) : "";
        if (!refused.empty())
            std::fprintf(stderr,
                         "jamsim run (rank %d): %s: writing the archive '%s' failed (%s); the replicas "
                         "finished before are safe in it (jamsim status %s): %s and run the same command "
                         "again to continue\n",
                         rank, refused.c_str(), decision.output.c_str(), e.what(), decision.output.c_str(),
                         refused == kNoSpaceLeft ? "free space" : "mend the filesystem");
        else if (dynamic_cast<const std::filesystem::filesystem_error*>(&e))
            std::fprintf(stderr,
                         "jamsim run (rank %d): the filesystem refused a checkpoint beside the archive (%s); the "
                         "replicas finished before and the checkpoints are kept: mend the filesystem (space, "
                         "quota, permissions) and run the same command again to continue\n",
                         rank, e.what());
        else
            std::fprintf(stderr, "jamsim run (rank %d): error: %s\n", rank, e.what());
        MPI_Abort(comm, 1);
    }
    return 0;
}

/// The options that describe the run a dry run plans (`jamsim run --dry-run`).
void add_dry_run_options(CLI::App& cmd, const std::shared_ptr<RunOptions>& opt) {
    cmd.add_option("--ranks", opt->plan.ranks, "--dry-run: ranks of the planned run")
        ->check(count_from_one_to("ranks", 1 << 20))  // as plan's nodes x cores (1e9 was blamed on the campaign)
        ->default_str("1");
    cmd.add_option("--shards", opt->plan.shards, "--dry-run: Slurm array tasks of the planned run")
        ->check(count_at_least_one("shards"))
        ->default_str("1");
    add_serial_fraction_option(cmd, opt->plan.serial_fraction);
    add_probe_seconds_option(cmd, opt->plan.probe_seconds);
    cmd.add_option_function<std::string>(
           "--time-limit",
           [opt](const std::string& v) {
               opt->plan.time_limit = parse_duration(v);
               if (!(opt->plan.time_limit > 0))
                   throw CLI::ValidationError(
                       "jamsim run: --time-limit = " + v +
                       " is not allowed: a duration > 0 such as 3600, 90min or 24h (at most 1e9 s)");
               opt->time_limit_text = v;
           },
           "--dry-run: a task's time limit, to count the requeues it needs")
        ->type_name("DURATION");
    cmd.add_flag("--summary", opt->plan.summary,
                 "--dry-run: one line per (model, N) with its work, longest replica and archive share, "
                 "instead of one per replica (`jamsim plan --costs` needs the full listing)");
    cmd.add_flag_callback(
        "--no-calibrate", [opt] { opt->plan.calibrate = false; },
        "--dry-run: nominal throughput instead of a short probe per model and N");
}

/// Options that mean nothing together: a dry run's plan options on a run, a run's own on a
/// dry run, and a time limit shorter than the warning's lead.
void check_option_combinations(RunOptions& opt, const CLI::App& cmd) {
    // The planned run's options describe a dry run's plan; a run takes its ranks from
    // mpirun and its time limit from Slurm, so there they would be silently ignored.
    if (!opt.dry_run)
        for (const char* name : {"--ranks", "--shards", "--time-limit", "--summary", "--no-calibrate",
                                 "--serial-fraction", "--probe-seconds"})
            if (cmd.count(name) > 0)
                throw CLI::ValidationError(std::string("jamsim run: ") + name +
                                           " is not allowed without --dry-run: it describes the run a dry run "
                                           "plans (a run's ranks are mpirun's -n, its time limit Slurm's)");
    // And a run's own options describe nothing a dry run does: it starts no replica.
    if (opt.dry_run)
        for (const char* name :
             {"--shard", "--retry-failed", "--checkpoint-every", "--progress", "--progress-interval"})
            if (cmd.count(name) > 0)
                throw CLI::ValidationError(
                    std::string("jamsim run: ") + name +
                    " is not allowed with --dry-run: it changes how a run runs, and a dry run starts none" +
                    (std::string_view(name) == "--shard"
                         ? " (the dry run of the whole campaign plans its shards: --shards N --time-limit T)"
                         : ""));
    if (cmd.count("--no-calibrate") > 0 && cmd.count("--probe-seconds") > 0)
        throw CLI::ValidationError("jamsim run: --probe-seconds is not allowed with --no-calibrate: nominal "
                                   "throughput probes nothing");
    if (opt.plan.time_limit > 0) {
        opt.plan.signal_lead = signal_lead_from_environment();
        // Slurm may send the warning up to a minute early (its event timer's period).
        const double least = opt.plan.signal_lead + 60;
        if (opt.plan.time_limit <= least)
            throw CLI::ValidationError(
                "jamsim run: --time-limit = " + opt.time_limit_text + " is not allowed: longer than " +
                show_value(least) + " s, the warning's lead (JAMSIM_SIGNAL_LEAD = " + show_value(opt.plan.signal_lead) +
                " s) plus the minute by which Slurm may send it early: no task could work");
    }
}

}  // namespace

CLI::App* add_run_command(CLI::App& app, int& argc, char**& argv) {
    auto opt = std::make_shared<RunOptions>();
    auto* cmd = app.add_subcommand("run", "Run a campaign over MPI ranks into one HDF5 archive");
    cmd->add_option("campaign", opt->spec_path, "Campaign file (TOML)")->required()->type_name("FILE");
    cmd->add_option("-o,--output", opt->output, "Archive path (overrides [campaign] output)")
        ->check(nonempty_path())
        ->type_name("FILE");
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
        ->default_str("10")
        ->type_name("SECONDS");
    cmd->add_flag("--retry-failed", opt->retry_failed,
                  "Run the failed replicas of an existing archive again, besides the pending ones "
                  "(after a fix to the code or the machine; their parameters are the campaign's, so a "
                  "failure that they cause comes back; with a new archive there is nothing to retry)");
    cmd->add_option_function<std::string>(
           "--checkpoint-every",
           [opt](const std::string& v) {
               opt->checkpoint_seconds = parse_duration(v);
               if (opt->checkpoint_seconds < 0)
                   throw CLI::ValidationError(
                       "jamsim run: --checkpoint-every = " + v +
                       " is not allowed: a duration >= 0 such as 300, 90s, 15min or 2h (at most 1e9 s)");
           },
           "Save each running replica's state at its first checkpoint step after this long "
           "(0: at every checkpoint step; [run] checkpoint_steps sets the steps)")
        ->default_str("300s")
        ->type_name("DURATION");
    cmd->add_option("--max-replicas", opt->max_replicas,
                    "Refuse a campaign of more replicas (a typo in seeds or a sweep list)")
        ->check(count_at_least_one("replicas"))
        ->capture_default_str();
    cmd->add_option_function<std::string>(
           "--max-archive-size",
           [opt](const std::string& v) {
               opt->limits.max_archive_bytes = parse_bytes(v);
               if (!(opt->limits.max_archive_bytes > 0))
                   throw CLI::ValidationError(
                       "jamsim run: --max-archive-size = " + v +
                       " is not allowed: a size in decimal from 1 byte to about 1e308 such as 500G, 2T or 1e13");
           },
           "Refuse a campaign whose archive would be larger (the free space of its filesystem is "
           "checked as well)")
        ->default_str("1T")
        ->type_name("SIZE");
    add_dry_run_options(*cmd, opt);
    cmd->add_option("--shard", opt->shard,
                    "K/N: run only replicas with id % N == K, rate ladders whole (ladder k % N == K; merge shards "
                    "with jamsim merge)")
        ->type_name("K/N");
    cmd->add_option("--progress", opt->progress, "auto (redraw on a terminal), lines (log files) or redraw")
        ->type_name("MODE")
        ->check(CLI::IsMember({"auto", "lines", "redraw"}))
        ->capture_default_str();
    cmd->callback([opt, cmd, &argc, &argv] {
        check_threads_environment("jamsim run", true);
        check_option_combinations(*opt, *cmd);
        parse_shard(opt->shard);  // bad value: message and exit before MPI starts
        const int rc = run(*opt, argc, argv);
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
    return cmd;
}

}  // namespace jamsim::app
