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

// `jamsim status` and `jamsim merge`: the commands that read (and merge) finished or running
// archives, beside `jamsim run` (campaign_commands.cpp).
namespace jamsim::app {

namespace {

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
    const std::string unfinished =
        live ? "running now: a live run holds the archive's lock"
             : "interrupted: no run holds the archive; run the same command again to continue";
    std::string state = complete ? "complete: every replica is finished" : run_finished ? "" : unfinished;
    if (complete && !s.merged.empty()) state += "; merged " + s.merged;
    std::printf("last run started %s, finished %s%s\n", s.started.empty() ? "-" : s.started.c_str(),
                run_finished ? s.finished.c_str() : "-", state.empty() ? "" : (" (" + state + ")").c_str());
    if (s.cost_done > 0 && s.cost_left > 0) {
        const double per_cost = s.wall_seconds_done / s.cost_done;
        const double ranks = s.ranks > 0 ? static_cast<double>(s.ranks) : 1.0;
        std::printf("remaining: about %.0f s on %lld ranks (%.0f core-seconds)\n", per_cost * s.cost_left / ranks,
                    static_cast<long long>(ranks), per_cost * s.cost_left);
    }
    for (const auto& r : s.in_progress)
        std::printf("%s replica %lld: %.1f%% of its steps at its last checkpoint\n", live ? "running" : "interrupted",
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
int merge(const std::string& output, const std::vector<std::string>& inputs, int& argc, char**& argv) {
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
            std::fprintf(stderr,
                         "jamsim merge: '%s' belongs to a different campaign than '%s': %s "
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
                } catch (const std::exception& e) { differs = std::string("cannot be compared: ") + e.what(); }
                if (!differs.empty()) {
                    std::fprintf(stderr,
                                 "jamsim merge: the replica %s is in '%s' (replica %zu) and '%s' "
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
    Archive out = exists ? Archive::open(MPI_COMM_SELF, output) : Archive::create(MPI_COMM_SELF, output, spec);
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

}  // namespace

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
        } catch (const std::exception& e) { std::fprintf(stderr, "jamsim merge: %s\n", e.what()); }
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
        } catch (const std::exception& e) { std::fprintf(stderr, "jamsim status: %s\n", e.what()); }
        if (rc != 0) throw CLI::RuntimeError(rc);
    });
    return cmd;
}

}  // namespace jamsim::app
