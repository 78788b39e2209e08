// The run of a checked campaign over MPI ranks (lifecycle.hpp, run_campaign): the archive's
// lock, extending or growing the archive, creating or opening it, the farm, the totals.
#include <algorithm>
#include <filesystem>
#include <optional>

#include "jamsim/archive/archive.hpp"
#include "jamsim/archive/archive_lock.hpp"
#include "jamsim/campaign/lifecycle.hpp"
#include "jamsim/campaign/run_checks.hpp"
#include "jamsim/campaign/scheduler.hpp"
#include "jamsim/campaign/stop_request.hpp"
#include "jamsim/io/checkpoint_file.hpp"
#include "jamsim/parallel/mpi.hpp"
#include "jamsim/parallel/threads.hpp"

namespace jamsim {

namespace {

void say(const RunSettings& settings, int rank, const std::string& line) {
    if (rank == 0 && settings.say) settings.say(line);
}

/// Extends or grows the archive in place when check_run decided so (collective).
void reshape_archive(MPI_Comm comm, const CampaignSpec& spec, const RunDecision& d, const RunSettings& settings,
                     ArchiveLock& lock) {
    const int rank = mpi::rank(comm);
    if (d.mode == OutputMode::Extend) {
        say(settings, rank,
            "extending " + d.output + " to the longer runs of " + settings.spec_path +
                ": finished replicas continue from their final checkpoints" +
                (spec.predecessor.empty()
                     ? ""
                     : "; a rate ladder's later replicas run again from their predecessors' new end states"));
        Archive::extend(comm, d.output, spec);
        lock.hold_archive(d.output);  // the file was replaced
    }
    if (d.mode == OutputMode::Grow) {
        const auto added = static_cast<std::int64_t>(spec.replicas.size()) - d.grow_kept;
        say(settings, rank,
            "growing archive " + d.output + ": " + std::to_string(d.grow_kept) + " replicas kept, " +
                std::to_string(added) + " new");
        Archive::grow(comm, d.output, spec, d.grow_source);
        lock.hold_archive(d.output);
    }
}

/// A new archive, created by every rank together; "" or why the creation failed (then no
/// partial file is left, on every rank alike).
std::string create_archive(MPI_Comm comm, const CampaignSpec& spec, const std::string& output,
                           std::optional<Archive>& created) {
    std::string why;
    try {
        created.emplace(Archive::create(comm, output, spec));
    } catch (const h5::Error& e) { why = e.what(); }
    int failed = !why.empty(), any = 0;
    mpi::check(MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, comm), "MPI_Allreduce");
    if (!any) return "";
    created.reset();
    std::error_code ignored;
    if (mpi::rank(comm) == 0) {
        std::filesystem::remove(output, ignored);
        std::filesystem::remove(Archive::creation_marker(output), ignored);
    }
    const std::string refused = write_refused(output);
    return spec.path + ": creating the archive '" + output + "' failed" + (refused.empty() ? "" : ": " + refused) +
           "; nothing was kept (" + (why.empty() ? "on another rank" : why) + ")";
}

/// "" when the archive is still as check_run found it, now that this run holds its lock (on
/// every rank alike); else why the run stops. Between the checks and the lock another run may
/// have made, replaced, extended or grown it: this run must not write into another
/// campaign's archive. (The same campaign's archive made meanwhile is resumed, as it would be.)
std::string changed_since_checks(MPI_Comm comm, const CampaignSpec& spec, const RunDecision& d) {
    std::string why;
    if (mpi::rank(comm) == 0) {
        OutputMode mode = OutputMode::Fresh;
        std::vector<std::int64_t> source;
        try {
            why = check_output(d.output, d.output_given, spec, mode, source);
        } catch (const std::exception& e) { why = e.what(); }  // every rank must hear of it
        if (why.empty() && (mode != d.mode || source != d.grow_source)) why = "it is no longer as this run found it";
        if (const std::string prefix = spec.path + ": "; why.rfind(prefix, 0) == 0) why.erase(0, prefix.size());
        if (!why.empty())
            why = spec.path + ": the archive '" + d.output +
                  "' changed while this run started (another run made or changed it): " + why +
                  "; nothing was done (run the same command again to check it anew)";
    }
    mpi::broadcast(why, 0, comm);
    return why;
}

/// The farm's counts summed over the ranks onto rank 0.
void add_up(MPI_Comm comm, const FarmSummary& s, RunOutcome& out) {
    long long local[5] = {s.ran, s.failed, s.resumed, s.interrupted, s.skipped}, total[5] = {};
    mpi::check(MPI_Reduce(local, total, 5, MPI_LONG_LONG, MPI_SUM, 0, comm), "MPI_Reduce");
    double times[2] = {s.io_seconds, s.wall_seconds}, sums[2] = {};
    mpi::check(MPI_Reduce(times, sums, 2, MPI_DOUBLE, MPI_SUM, 0, comm), "MPI_Reduce");
    out.ran = total[0];
    out.failed = total[1];
    out.resumed = total[2];
    out.interrupted = total[3];
    out.skipped = s.skipped;  // rank 0 decides what is skipped
    out.wall_seconds = s.wall_seconds;
    out.io_share = sums[1] > 0 ? sums[0] / sums[1] : 0.0;
}

}  // namespace

RunOutcome run_campaign(MPI_Comm comm, const CampaignSpec& spec, const RunDecision& d, const RunSettings& settings) {
    const int rank = mpi::rank(comm);
    RunOutcome out;
    // One writer per archive: from here on this run holds it (refused while another lives).
    std::optional<ArchiveLock> lock;
    try {
        lock.emplace(ArchiveLock::acquire(comm, d.output, "jamsim run " + settings.spec_path));
        lock->hold_archive(d.output);
    } catch (const ArchiveBusy& e) {
        out.end = RunOutcome::End::refused;
        out.refusal = e.what();
        return out;
    }
    const auto refuse = [&](std::string why) {
        lock->release();
        out.end = RunOutcome::End::refused;
        out.refusal = std::move(why);
        return out;
    };
    if (std::string changed = changed_since_checks(comm, spec, d); !changed.empty()) return refuse(std::move(changed));
    int exists = 0;
    std::optional<Archive> created;
    bool reshaped = false;  // extended or grown in place
    try {
        reshape_archive(comm, spec, d, settings, *lock);
        reshaped = d.mode == OutputMode::Extend || d.mode == OutputMode::Grow;
        exists = rank == 0 ? std::filesystem::exists(d.output) : 0;
        mpi::broadcast(exists, 0, comm);
        if (exists) created.emplace(Archive::open(comm, d.output));
    } catch (const h5::OpenRefused& e) {  // alike on every rank, and nothing is open
        if (rank == 0) {                  // what a refused extension or growth made beside the archive
            try {
                (void)Archive::finish_growth(d.output);
                (void)Archive::remove_interrupted_extension(d.output);
            } catch (const h5::Error&) {}  // the next run removes it, with a note
        }
        return refuse(spec.path + ": " + e.what() +
                      (reshaped
                           ? std::string("; the archive was ") + (d.mode == OutputMode::Extend ? "extended" : "grown") +
                                 " first, and nothing has run in it since"
                           : "; nothing was changed"));
    }
    if (!exists)
        if (std::string why = create_archive(comm, spec, d.output, created); !why.empty()) return refuse(why);
    Archive archive = std::move(*created);
    if (!exists) lock->hold_archive(d.output);
    try {
        archive.stamp("run_started");  // closes and reopens the archive
    } catch (const h5::OpenRefused& e) { return refuse(spec.path + ": " + e.what() + "; nothing has run"); }
    std::optional<InitialStates> initial;
    if (!spec.replicas.front().initial.empty()) initial.emplace(spec.replicas.front().initial);
    const FarmOptions farm{.progress = settings.progress,
                           .shard = settings.shard,
                           .retry_failed = settings.retry_failed,
                           .archive_path = d.output,
                           .checkpoint_seconds = settings.checkpoint_seconds,
                           .initial_states = initial ? &*initial : nullptr};
    const int ranks = mpi::size(comm), threads = kernel_threads();
    say(settings, rank,
        "campaign " + spec.name + ": " + std::to_string(spec.replicas.size()) + " replicas on " +
            std::to_string(ranks) + (ranks == 1 ? " rank" : " ranks") + " x " + std::to_string(threads) +
            (threads == 1 ? " thread" : " threads") + " -> " + d.output +
            (!exists                 ? ""
             : settings.retry_failed ? " (resuming: done replicas are skipped, failed ones run again)"
                                     : " (resuming: finished replicas are skipped)"));
    if (const Shard& shard = settings.shard; shard.count > 1) {
        const auto chains = static_cast<std::int64_t>(chains_of(spec.predecessor, spec.replicas.size()).members.size());
        if (shard.index >= chains)  // chain c is in shard c % count
            say(settings, rank,
                "shard " + std::to_string(shard.index) + "/" + std::to_string(shard.count) +
                    " holds no replica: the campaign has " + std::to_string(chains) +
                    (spec.predecessor.empty() ? (chains == 1 ? " replica" : " replicas")
                                              : (chains == 1 ? " chain" : " chains") +
                                                    std::string(" (rate ladders, each whole in one shard)")) +
                    ", in shards 0 to " + std::to_string(std::min<std::int64_t>(chains, shard.count) - 1) +
                    "; this shard's archive holds them all pending, for jamsim merge");
    }
    const FarmSummary summary = run_farm(comm, spec, archive, farm);
    add_up(comm, summary, out);
    // Interrupted (a signal, or a replica stopped at a checkpoint step) on any rank?
    int stopped = 0, local_stopped = StopRequest::requested() || summary.interrupted > 0;
    mpi::check(MPI_Allreduce(&local_stopped, &stopped, 1, MPI_INT, MPI_MAX, comm), "MPI_Allreduce");
    if (stopped) {
        archive.close();
        lock->release();
        out.end = RunOutcome::End::interrupted;
        return out;
    }
    try {
        archive.stamp("run_finished");
    } catch (const h5::OpenRefused& e) {
        return refuse(spec.path + ": " + e.what() + " at the run's end: every replica's data are in the archive, " +
                      "only the time it finished is not");
    }
    archive.close();
    lock->release();
    if (rank == 0) {  // the checkpoint folder, once every replica has removed its own
        std::error_code ignored;
        std::filesystem::remove(checkpoint_folder(d.output), ignored);  // only if empty
    }
    return out;
}

}  // namespace jamsim
