#include "campaign_commands.hpp"
#include "option_checks.hpp"
#include "exit_status.hpp"
#include "wall_time.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "jamsim/archive/archive.hpp"
#include "jamsim/archive/archive_file_check.hpp"
#include "jamsim/archive/archive_lock.hpp"
#include "jamsim/campaign/lifecycle.hpp"
#include "jamsim/campaign/throughput.hpp"
#include "jamsim/campaign/wall_time.hpp"
#include "jamsim/parallel/mpi.hpp"

// `jamsim status` and `jamsim merge`: the commands that read (and merge) finished or running
// archives, beside `jamsim run` (campaign_commands.cpp).
namespace jamsim::app {

namespace {

/// "remaining: about T on R ranks (C core-seconds[; the longest chain left, ... sets it])":
/// each unfinished replica's estimated cost at the throughput of the finished replicas of its
/// (model, N, phi) group (campaign/throughput.hpp: else its model and N, ...), a running one
/// from its latest progress while the run lives, from its last checkpoint (where it resumes)
/// when interrupted; on the latest run's ranks, and never below the longest unfinished chain.
void print_time_left(const std::string& path, const ArchiveSummary& s, bool live) {
    const double ranks = s.ranks > 0 ? static_cast<double>(s.ranks) : 1.0;
    std::vector<double> progress = s.progress;
    for (const auto& r : s.in_progress)
        if (live && std::isfinite(r.noted) && static_cast<std::size_t>(r.replica) < progress.size())
            progress[static_cast<std::size_t>(r.replica)] = std::max(r.fraction, r.noted);
    TimeLeft left;
    try {
        const StoredCampaign stored = read_stored_campaign(path);
        left = time_left(stored.spec, stored.status, s.wall_seconds, progress);
    } catch (const std::exception&) {  // a campaign this build cannot read back: one rate for all
        left.core_seconds = s.wall_seconds_done / s.cost_done * s.cost_left;
    }
    const bool chain_bound = left.longest_chain > left.core_seconds / ranks;
    std::printf("remaining: about %s on %s (%.0f core-seconds%s)\n", duration(left.on(ranks)).c_str(),
                counted(static_cast<long long>(ranks), "rank").c_str(), left.core_seconds,
                chain_bound ? "; the longest chain left, one replica after another, sets it" : "");
}

int status(const std::string& path) {
    if (const std::string bad = diagnose_archive_file(path); !bad.empty()) {
        std::fprintf(stderr, "jamsim status: %s\n", bad.c_str());
        return kExitRefused;
    }
    const ArchiveSummary s = summarize_archive(path);
    const long long total = s.pending + s.running + s.done + s.failed;
    std::printf("campaign %s (%s): %lld/%lld done, %lld running, %lld failed, %lld pending\n", s.campaign.c_str(),
                path.c_str(), static_cast<long long>(s.done), total, static_cast<long long>(s.running),
                static_cast<long long>(s.failed), static_cast<long long>(s.pending));
    // Complete: every replica done or failed, whether by runs or by merging shards (a merged
    // archive has no run of its own that finished).
    const bool complete = s.pending == 0 && s.running == 0;
    const bool run_finished = !s.finished.empty() && !(s.finished < s.started);
    // Running now or interrupted: a live run holds the archive's lock (archive/archive_lock.hpp).
    bool live = false;
    try {
        ArchiveLock::check_free(path);
    } catch (const ArchiveBusy&) { live = true; }
    // A merge's output that no run has continued since is not an interrupted run.
    // (Stamps have whole seconds: a run that started in the merge's second came after it.)
    const bool merged_since = !s.merged.empty() && (s.started.empty() || s.started < s.merged);
    const std::string unfinished =
        live           ? "running now: a live run holds the archive's lock"
        : merged_since ? "merged " + s.merged + ", not run since: jamsim run CAMPAIGN.toml -o " + path +
                             " runs the rest, with the campaign of its shards (or a file of the same replicas)"
                       : "interrupted: no run holds the archive; run the same command again to continue";
    std::string state = complete ? "complete: every replica is finished" : run_finished ? "" : unfinished;
    if (complete && !s.merged.empty()) state += "; merged " + s.merged;
    std::printf("last run started %s, finished %s%s\n", s.started.empty() ? "-" : s.started.c_str(),
                run_finished ? s.finished.c_str() : "-", state.empty() ? "" : (" (" + state + ")").c_str());
    if (s.cost_done > 0 && s.cost_left > 0) print_time_left(path, s, live);
    for (const auto& r : s.in_progress) {
        const auto id = static_cast<long long>(r.replica);
        if (!std::isfinite(r.noted) || (!live && r.noted <= r.fraction))
            std::printf("%s replica %lld: %.1f%% of its steps at its last checkpoint%s\n",
                        live ? "running" : "interrupted", id, 100.0 * r.fraction, live ? "" : ", where it continues");
        else if (live)
            std::printf("running replica %lld: %.1f%% of its steps (%.0f s ago), %.1f%% at its last checkpoint\n", id,
                        100.0 * r.noted, r.note_age, 100.0 * r.fraction);
        else
            std::printf("interrupted replica %lld: stopped at %.1f%% of its steps; %.1f%% at its last checkpoint, "
                        "where it continues\n",
                        id, 100.0 * r.noted, 100.0 * r.fraction);
    }
    for (const auto& f : s.failures) std::printf("failed %s\n", f.c_str());
    return 0;
}

/// `jamsim merge`: one process (merging is an archive's copy, not a computation).
int merge(const std::string& output, const std::vector<std::string>& inputs, int& argc, char**& argv) {
    mpi::Session session(argc, argv);
    if (mpi::size(MPI_COMM_WORLD) != 1) {
        std::fprintf(stderr, "jamsim merge: run it as one process (no mpirun -n > 1)\n");
        return kExitRefused;
    }
    MergeOutcome merged;
    try {
        merged = merge_archives(output, inputs);
    } catch (const CampaignRefused& e) {
        std::fprintf(stderr, "jamsim merge: %s\n", e.what());
        return kExitRefused;
    } catch (const MergeStopped& e) {  // Ctrl-C or SIGTERM between two replicas (main.cpp)
        std::fprintf(stderr, "jamsim merge: %s\n", e.what());
        return kExitInterrupted;
    } catch (const MergeFailed& e) {
        // A failed write leaves HDF5 a file it cannot close: the process ends at MPI_Finalize,
        // before HDF5's own close of it (h5::file_close_failed). The output is already removed
        // or whole (merge_archives).
        std::fprintf(stderr, "jamsim merge: %s\n", e.what());
        return 1;
    }
    std::printf("merged %lld %s from %zu %s into %s", static_cast<long long>(merged.copied),
                merged.copied == 1 ? "replica" : "replicas", inputs.size(), inputs.size() == 1 ? "archive" : "archives",
                output.c_str());
    if (merged.union_campaign) std::printf(" (a campaign of %zu replicas: the union of their sweeps)", merged.replicas);
    std::printf("\n");
    return status(output);
}

}  // namespace

CLI::App* add_merge_command(CLI::App& app, int& argc, char**& argv) {
    auto output = std::make_shared<std::string>();
    auto shards = std::make_shared<std::vector<std::string>>();
    auto* cmd = app.add_subcommand(
        "merge", "Merge archives into one: shards of one campaign (jamsim run --shard K/N), or "
                 "campaigns that differ only in their sweeps (the output holds the union of their replicas)");
    cmd->add_option("-o,--output", *output,
                    "Merged archive (created, or completed if it exists); without -o the first "
                    "archive named is the output")
        ->check(nonempty_path())
        ->type_name("FILE");
    cmd->add_option("archives", *shards, "[OUTPUT] then the archives to merge")->required()->type_name("FILE");
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
        } catch (const std::exception& e) { std::fprintf(stderr, "jamsim merge: %s\n", e.what()); }
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
    return cmd;
}

CLI::App* add_status_command(CLI::App& app) {
    auto path = std::make_shared<std::string>();
    auto* cmd = app.add_subcommand("status", "Summarise a campaign archive (also while running)");
    cmd->add_option("archive", *path, "Campaign archive (HDF5)")->required()->type_name("FILE");
    cmd->callback([path] {
        int rc = 1;
        try {
            rc = status(*path);
        } catch (const std::exception& e) { std::fprintf(stderr, "jamsim status: %s\n", e.what()); }
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
    return cmd;
}

}  // namespace jamsim::app
