#include "campaign_commands.hpp"
#include "exit_status.hpp"
#include "dry_run.hpp"
#include "run_checks.hpp"
#include "threads_option.hpp"
#include "wall_time.hpp"

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
#include "jamsim/archive/archive.hpp"
#include "jamsim/archive/capacity.hpp"
#include "jamsim/archive/archive_file_check.hpp"
#include "jamsim/archive/archive_lock.hpp"
#include "jamsim/io/checkpoint_file.hpp"
#include "jamsim/io/initial_states.hpp"
#include "jamsim/spec/campaign_spec.hpp"
#include "jamsim/linalg/contact_solver.hpp"
#include "jamsim/campaign/farm.hpp"
#include "jamsim/params/parameters.hpp"
#include "jamsim/run/model_registry.hpp"
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
    bool retry_failed = false;        // run failed replicas again
    double checkpoint_seconds = 300;  // save a running replica's state at most this often
    DryRunPlan plan;                  // what --dry-run estimates for
    std::int64_t max_replicas = kDefaultMaxReplicas;
    CapacityLimits limits;
};

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
    int extend = 0;                         // the archive holds this campaign with shorter runs: extend it
    int grow = 0;                           // the archive holds this campaign with fewer replicas: grow it
    std::vector<std::int64_t> grow_source;  // rank 0: the archive's id of each replica (−1: new)
    std::int64_t grow_kept = 0;
    const int node_ranks = opt.dry_run ? opt.plan.ranks : mpi::ranks_on_node(comm);
    const int ranks = opt.dry_run ? opt.plan.ranks : mpi::size(comm);
    if (!opt.dry_run)  // a note when --threads overrides OMP_NUM_THREADS; more threads than cores
        if (const std::string notes = threads_notes("jamsim run", comm); rank == 0) std::fputs(notes.c_str(), stderr);
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
                } catch (const h5::Error& e) { throw SpecError(spec.path + ": " + e.what()); }
            // A dry run writes nothing, but an existing archive it names must fit the campaign.
            OutputMode mode = OutputMode::Fresh;
            if (!opt.dry_run || std::filesystem::exists(output))
                error = check_output(output, spec, mode, grow_source);
            else
                error = check_output_folder(output, spec, false);  // what the run would refuse
            extend = mode == OutputMode::Extend;
            grow = mode == OutputMode::Grow;
            for (const std::int64_t from : grow_source) grow_kept += from >= 0;
            // The checkpoints beside the archive are keyed by its replica ids (before a growth,
            // those of the archive's campaign).
            if (error.empty()) error = check_checkpoints(output, grow ? read_stored_campaign(output).spec : spec);
            if (error.empty()) error = check_petsc_options(spec);
            if (error.empty()) print_advisories(spec);
            if (error.empty() && !spec.replicas.front().initial.empty()) {
                try {  // every replica must find its starting state before any work
                    const InitialStates source(spec.replicas.front().initial);
                    for (std::size_t id = 0; id < spec.replicas.size(); ++id)
                        source.match(spec.replicas[id], static_cast<std::int64_t>(id));
                    if (std::filesystem::exists(output))
                        error = initial_source_changed(source, spec, output, grow_source);
                } catch (const InitialStateError& e) { error = spec.path + ": " + e.what(); }
            }
        } catch (const SpecError& e) {
            error = e.what();
        } catch (const std::exception& e) {           // any other failure of rank 0's checks (an unreadable
            error = opt.spec_path + ": " + e.what();  // file): said on every rank, never left unbroadcast
        }
        // An archive that another live run writes is refused for that reason, whatever it
        // looks like now (it may be half created): the holder's name says what to do.
        if (!opt.dry_run && !output.empty()) try {
                ArchiveLock::check_free(output);
            } catch (const ArchiveBusy& e) { error = e.what(); }
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
                            "replica continuing from its final checkpoint)\n",
                            output.c_str());
            if (grow)
                std::printf("(%s holds this campaign with fewer replicas: the run would grow it, keeping "
                            "%lld replicas and running %lld new ones)\n",
                            output.c_str(), static_cast<long long>(grow_kept),
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
                            "their final checkpoints%s\n",
                            output.c_str(), opt.spec_path.c_str(),
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
            } catch (const h5::Error& e) { why = e.what(); }
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
            std::printf("campaign %s: %zu replicas on %d rank%s x %d thread%s -> %s%s\n", spec.name.c_str(),
                        spec.replicas.size(), mpi::size(comm), mpi::size(comm) == 1 ? "" : "s", kernel_threads(),
                        kernel_threads() == 1 ? "" : "s", output.c_str(),
                        !exists            ? ""
                        : opt.retry_failed ? " (resuming: done replicas are skipped, failed ones run again)"
                                           : " (resuming: finished replicas are skipped)");
        const FarmSummary s = run_farm(comm, spec, archive, farm);
        double io = 0, wall = 0, local_io = s.io_seconds, local_wall = s.wall_seconds;
        // Interrupted (a signal, or a replica stopped at a checkpoint step) on any rank?
        int stopped = 0, local_stopped = StopRequest::requested() || s.interrupted > 0;
        mpi::check(MPI_Allreduce(&local_stopped, &stopped, 1, MPI_INT, MPI_MAX, comm), "MPI_Allreduce");
        long long interrupted = 0, local_interrupted = s.interrupted;
        mpi::check(MPI_Reduce(&local_interrupted, &interrupted, 1, MPI_LONG_LONG, MPI_SUM, 0, comm), "MPI_Reduce");
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
        mpi::check(MPI_Reduce(&local_failed, &failed, 1, MPI_LONG_LONG, MPI_SUM, 0, comm), "MPI_Reduce");
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
            std::fprintf(stderr,
                         "jamsim run (rank %d): no space left on device: writing the archive '%s' "
                         "failed (%s); the replicas finished before are safe in it (jamsim status "
                         "%s): free space and run the same command again to continue\n",
                         rank, output.c_str(), e.what(), output.c_str());
        else
            std::fprintf(stderr, "jamsim run (rank %d): error: %s\n", rank, e.what());
        MPI_Abort(comm, 1);
    }
    return 0;
}

}  // namespace

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
        ->check(CLI::PositiveNumber)
        ->default_str("1");
    cmd->add_option("--shards", opt->plan.shards, "--dry-run: Slurm array tasks of the planned run")
        ->check(CLI::PositiveNumber)
        ->default_str("1");
    add_serial_fraction_option(*cmd, opt->plan.serial_fraction);
    cmd->add_option_function<std::string>(
        "--time-limit",
        [opt](const std::string& v) {
            opt->plan.time_limit = parse_duration(v);
            if (!(opt->plan.time_limit > 0))
                throw CLI::ValidationError("jamsim run: --time-limit = " + v +
                                           " is not allowed: a duration > 0 such as 3600, 90min or 24h");
        },
        "--dry-run: a task's time limit, to count the requeues it needs");
    cmd->add_flag("--summary", opt->plan.summary,
                  "--dry-run: one line per (model, N) with its work, longest replica and archive share, "
                  "instead of one per replica (`jamsim plan --costs` needs the full listing)");
    cmd->add_flag("!--no-calibrate", opt->plan.calibrate,
                  "--dry-run: nominal throughput instead of a short probe per model and N");
    cmd->add_option("--shard", opt->shard,
                    "K/N: run only replicas with id % N == K, rate ladders whole (ladder k % N == K; merge shards "
                    "with jamsim merge)");
    cmd->add_option("--progress", opt->progress, "auto (redraw on a terminal), lines (log files) or redraw")
        ->check(CLI::IsMember({"auto", "lines", "redraw"}))
        ->capture_default_str();
    cmd->callback([opt, &argc, &argv] {
        parse_shard(opt->shard);  // bad value: message and exit before MPI starts
        const int rc = run(*opt, argc, argv);
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
    return cmd;
}

}  // namespace jamsim::app
