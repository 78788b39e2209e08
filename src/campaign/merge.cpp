// Merging archives (lifecycle.hpp, merge_archives): shards of one campaign, or campaigns that
// differ only in their sweeps, into one archive whose campaign holds them all.
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include "jamsim/archive/archive.hpp"
#include "jamsim/archive/archive_file_check.hpp"
#include "jamsim/archive/archive_lock.hpp"
#include "jamsim/campaign/lifecycle.hpp"
#include "jamsim/campaign/stop_request.hpp"
#include "jamsim/io/checkpoint_file.hpp"
#include "jamsim/params/parameters.hpp"

namespace jamsim {

namespace {

/// "N = 64, phi = 0.84, rate = 0.003, seed = 2": a replica for a person (sweep parameters).
std::string replica_label(const ReplicaParams& p) {
    return "N = " + std::to_string(p.n) + ", phi = " + show_value(p.phi) + ", rate = " + show_value(p.rate) +
           ", seed = " + std::to_string(p.seed);
}

/// Each input's campaign, checked: readable, of this version, and differing from the first
/// input's only in its sweeps.
std::vector<StoredCampaign> read_inputs(const std::string& output, const std::vector<std::string>& inputs) {
    std::vector<StoredCampaign> stored;
    for (std::size_t k = 0; k < inputs.size(); ++k) {
        const std::string& path = inputs[k];
        // (By name, link or path: './a.h5' for 'a.h5' merged into the input itself.)
        if (std::error_code ec; path == output || std::filesystem::equivalent(path, output, ec))
            throw CampaignRefused("'" + path + "' is both the output and an input" +
                                  (path == output ? std::string() : " ('" + output + "')") + ": name a new output");
        // The same file twice (by name, link or path) adds nothing, and its count misleads.
        for (std::size_t j = 0; j < k; ++j) {
            std::error_code ec;
            if (inputs[j] == path || std::filesystem::equivalent(inputs[j], path, ec))
                throw CampaignRefused("shard '" + path + "' is given twice (as '" + inputs[j] +
                                      "' too): name each shard once");
        }
        if (const std::string bad = diagnose_archive_file(path); !bad.empty()) throw CampaignRefused("shard " + bad);
        try {
            stored.push_back(read_stored_campaign(path));
        } catch (const std::exception& e) { throw CampaignRefused("shard '" + path + "': " + e.what()); }
        // The stored fingerprint must be this version's: a shard written by a version whose
        // results mean something else (an older fingerprint) is not merged with new ones.
        if (const Archive::Fit fit = Archive::check_existing(path, stored.back().spec);
            fit.kind != Archive::Fit::Kind::Same)
            throw CampaignRefused("shard '" + path + "': " + fit.why);
        if (const std::string differs = settings_difference(stored.front().spec, stored.back().spec,
                                                            "'" + inputs.front() + "'", "'" + path + "'");
            !differs.empty())
            throw CampaignRefused("'" + path + "' belongs to a different campaign than '" + inputs.front() +
                                  "': " + differs + " (archives merge when they differ only in their sweeps)");
    }
    return stored;
}

/// The output's campaign: an input's own when it holds every replica (shards of one campaign),
/// else one written for the union of their replicas (points with their own seeds).
CampaignSpec merged_campaign(const std::string& output, const std::vector<std::string>& inputs,
                             const std::vector<StoredCampaign>& stored) {
    std::map<std::string, std::size_t> in_union;  // each replica once, by its identity
    std::vector<ReplicaParams> all;
    for (const auto& s : stored)
        for (const ReplicaParams& p : s.spec.replicas)
            if (in_union.emplace(describe(p), all.size()).second) all.push_back(p);
    for (const auto& s : stored) {
        std::set<std::string> own;
        for (const ReplicaParams& p : s.spec.replicas) own.insert(describe(p));
        if (own.size() == all.size() && s.spec.replicas.size() == all.size()) return s.spec;
    }
    std::string from;
    for (const auto& path : inputs) from += (from.empty() ? "" : ", ") + path;
    std::optional<CampaignSpec> merged;
    try {
        merged = parse_campaign(campaign_text(stored.front().spec.name, output, all,
                                              "The campaign of jamsim merge " + from +
                                                  ":\nthe union of their replicas, points with their own seeds."),
                                output + " (merged campaign)", std::numeric_limits<std::int64_t>::max());
    } catch (const SpecError& e) {
        throw CampaignRefused(std::string("cannot describe the merged campaign: ") + e.what());
    }
    bool same = merged->replicas.size() == all.size();
    for (const ReplicaParams& p : merged->replicas) same = same && in_union.count(describe(p));
    if (!same)
        throw CampaignRefused("the merged campaign does not hold the replicas of its inputs (a rate ladder whose "
                              "chains differ between them?): refusing");
    return *merged;
}

/// Each input replica's id in the output (the same id for shards of the output's campaign).
std::vector<std::vector<std::int64_t>> output_ids(const CampaignSpec& spec, const std::vector<StoredCampaign>& stored) {
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
    return target;
}

/// A replica finished in two inputs must be the same, bitwise.
void check_duplicates_agree(const std::vector<std::string>& inputs, const std::vector<StoredCampaign>& stored,
                            const std::vector<std::vector<std::int64_t>>& target) {
    std::map<std::int64_t, std::pair<std::size_t, std::size_t>> first_done;  // output id -> (input, id)
    for (std::size_t k = 0; k < stored.size(); ++k)
        for (std::size_t r = 0; r < stored[k].status.size(); ++r) {
            if (stored[k].status[r] != ReplicaStatus::Done) continue;
            const auto [it, fresh] = first_done.emplace(target[k][r], std::pair{k, r});
            if (fresh) continue;
            if (StopRequest::requested())  // comparing many duplicates can take minutes
                throw MergeStopped("merging was stopped by a signal before it wrote anything");
            const auto [j, q] = it->second;
            std::string differs;
            try {
                differs = Archive::replica_difference(inputs[j], static_cast<std::int64_t>(q), inputs[k],
                                                      static_cast<std::int64_t>(r));
            } catch (const std::exception& e) { differs = std::string("cannot be compared: ") + e.what(); }
            if (!differs.empty())
                throw CampaignRefused("the replica " + replica_label(stored[k].spec.replicas[r]) + " is in '" +
                                      inputs[j] + "' (replica " + std::to_string(q) + ") and '" + inputs[k] +
                                      "' (replica " + std::to_string(r) + ") with different data (" + differs +
                                      "): refusing to merge them");
        }
}

/// The existing output must be an archive of the merged campaign (one that an interrupted
/// merge or run of it left). Another campaign's archive, even one of the inputs' sweeps, cannot
/// take the union: say so, and how to merge into a new file instead.
void check_existing_output(const std::string& output, const std::vector<std::string>& inputs,
                           const CampaignSpec& spec) {
    if (const std::string bad = diagnose_archive_file(output); !bad.empty())
        throw CampaignRefused("refusing the output: " + bad);
    const Archive::Fit fit = Archive::check_existing(output, spec);
    if (fit.kind == Archive::Fit::Kind::Same) return;
    if (fit.kind == Archive::Fit::Kind::Refused) throw CampaignRefused("refusing: " + fit.why);
    std::string named = output;
    for (const auto& path : inputs) named += " " + path;
    const std::string merged =
        inputs.size() == 1 ? "'" + inputs.front() + "'"
                           : "the merge of " + std::to_string(inputs.size()) + " archives (the union of their sweeps)";
    throw CampaignRefused("refusing: '" + output + "' exists and holds another campaign than " + merged + ", of " +
                          std::to_string(spec.replicas.size()) +
                          " replicas; an existing output must hold that campaign already (as an interrupted merge "
                          "leaves it). To add these replicas to those of '" +
                          output + "', merge them all into a new file: jamsim merge NEW.h5 " + named + " (" + fit.why +
                          ")");
}

/// A rate ladder's replica that is done while its successor is not: its end state (which the
/// successor starts from) copied beside the output from an input that holds it. Without it,
/// the successor's run makes it again by running the chain, so a copy that fails is a warning.
void copy_ladder_end_states(const std::string& output, const std::vector<std::string>& inputs, const CampaignSpec& spec,
                            const std::vector<ReplicaStatus>& have,
                            const std::multimap<std::size_t, std::pair<std::size_t, std::size_t>>& done_in) {
    namespace fs = std::filesystem;
    for (std::size_t next = 0; next < spec.predecessor.size(); ++next) {
        const std::int64_t before = spec.predecessor[next];
        if (before < 0 || have[next] == ReplicaStatus::Done ||
            have[static_cast<std::size_t>(before)] != ReplicaStatus::Done)
            continue;
        const std::string copy = end_state_path(output, before);
        std::error_code ec;
        const auto [first, last] = done_in.equal_range(static_cast<std::size_t>(before));
        for (auto from = first; from != last && !fs::exists(copy, ec); ++from) {
            const std::string source =
                end_state_path(inputs[from->second.first], static_cast<std::int64_t>(from->second.second));
            if (!fs::exists(source, ec)) continue;
            fs::create_directories(checkpoint_folder(output), ec);
            // Written beside its place, then renamed into it: a kill leaves no partial end state.
            if (!ec) fs::copy_file(source, copy + ".tmp", fs::copy_options::overwrite_existing, ec);
            if (!ec) fs::rename(copy + ".tmp", copy, ec);
            if (ec)
                std::fprintf(stderr,
                             "jamsim merge: warning: cannot copy the end state '%s' to '%s' (%s): the run of "
                             "replica %zu makes it again\n",
                             source.c_str(), copy.c_str(), ec.message().c_str(), next);
        }
    }
}

/// copy_replicas' work on the open output: every finished replica of the inputs that it lacks
/// (a done one wins over a failed one), the ladders' end states, the stamp.
void fill(Archive& out, const std::string& output, const std::vector<std::string>& inputs, const CampaignSpec& spec,
          const std::vector<StoredCampaign>& stored, const std::vector<std::vector<std::int64_t>>& target,
          MergeOutcome& result) {
    std::vector<ReplicaStatus> have = out.read_status();
    std::multimap<std::size_t, std::pair<std::size_t, std::size_t>> done_in;  // output id -> (input, id) it came from
    for (std::size_t k = 0; k < inputs.size(); ++k)
        for (std::size_t r = 0; r < stored[k].status.size(); ++r) {
            const ReplicaStatus s = stored[k].status[r];
            const auto t = static_cast<std::size_t>(target[k][r]);
            if (s == ReplicaStatus::Done) done_in.emplace(t, std::pair{k, r});
            const bool finished = s == ReplicaStatus::Done || s == ReplicaStatus::Failed;
            if (!finished || have[t] == ReplicaStatus::Done) continue;
            if (have[t] == ReplicaStatus::Failed && s == ReplicaStatus::Failed) continue;
            if (StopRequest::requested()) throw MergeStopped("stopped by a signal");
            out.import_replica(inputs[k], static_cast<std::int64_t>(r), static_cast<std::int64_t>(t));
            have[t] = s;
            ++result.copied;
        }
    copy_ladder_end_states(output, inputs, spec, have, done_in);
    out.stamp("merged");
    out.close();
}

/// The copy itself, under the output's lock (fill).
void copy_replicas(const std::string& output, const std::vector<std::string>& inputs, const CampaignSpec& spec,
                   const std::vector<StoredCampaign>& stored, const std::vector<std::vector<std::int64_t>>& target,
                   bool exists, MergeOutcome& result) {
    Archive out = exists ? Archive::open(MPI_COMM_SELF, output) : Archive::create(MPI_COMM_SELF, output, spec);
    try {
        fill(out, output, inputs, spec, stored, target, result);
    } catch (...) {  // closed before the caller lets the lock go: no late flush after another writer came
        try {
            out.close();
        } catch (...) {}
        throw;
    }
}

}  // namespace

MergeOutcome merge_archives(const std::string& output, const std::vector<std::string>& inputs) {
    if (inputs.empty()) throw CampaignRefused("no archives to merge (jamsim merge -o OUT A.h5 B.h5 ...)");
    const std::vector<StoredCampaign> stored = read_inputs(output, inputs);
    const CampaignSpec spec = merged_campaign(output, inputs, stored);
    const auto target = output_ids(spec, stored);
    check_duplicates_agree(inputs, stored, target);
    if (const std::string why = output_path_problem(output); !why.empty())
        throw CampaignRefused("refusing the output: " + why);
    if (const std::filesystem::path folder = std::filesystem::path(output).parent_path(); !folder.empty()) {
        std::error_code ec;
        if (!std::filesystem::is_directory(folder, ec))
            throw CampaignRefused("refusing the output '" + output + "': a file in an existing folder ('" +
                                  folder.string() + "' " +
                                  (std::filesystem::exists(folder, ec) ? "is not a folder" : "does not exist") + ")");
    }
    try {  // an output whose creation a kill interrupted is made anew; Open MPI's lock files
        // that a killed merge or run left beside it go
        ArchiveLock::check_free(output);
        if (std::filesystem::exists(Archive::creation_marker(output))) (void)Archive::undo_interrupted_creation(output);
        (void)remove_stale_mpi_locks(output);
    } catch (const ArchiveBusy& e) { throw CampaignRefused(e.what()); }
    bool exists = std::filesystem::exists(output);
    if (std::string too_large = check_capacity(estimate_capacity(spec, output, 1, 1), {}, spec, output);
        !too_large.empty()) {
        // Said of the output, not of the campaign file the archives were once run from.
        if (too_large.starts_with(spec.path + ": ")) too_large.erase(0, spec.path.size() + 2);
        throw CampaignRefused(too_large);
    }
    // A refused output is refused before its lock file is made (which a refusal would leave
    // behind); checked again under the lock, as the file may change in between.
    if (exists) check_existing_output(output, inputs, spec);
    // The output is written by this process alone, and no input may still be written.
    std::optional<ArchiveLock> lock;
    try {
        for (const auto& path : inputs) ArchiveLock::check_free(path);
        lock.emplace(ArchiveLock::acquire(MPI_COMM_SELF, output, "jamsim merge"));
    } catch (const ArchiveBusy& e) { throw CampaignRefused(e.what()); }
    // Again under the lock: another merge may have made the output in between (a new output
    // would be truncated, and a failure would remove it).
    exists = std::filesystem::exists(output);
    if (exists) check_existing_output(output, inputs, spec);
    std::error_code ec;
    const bool had_checkpoints = std::filesystem::exists(checkpoint_folder(output), ec);
    if (StopRequest::requested()) {  // before a new output's creation (large for a large campaign)
        lock->release();
        throw MergeStopped("merging into '" + output + "' was stopped by a signal before it wrote anything");
    }
    MergeOutcome result{.replicas = spec.replicas.size(),
                        .union_campaign = fingerprint(spec) != fingerprint(stored.front().spec)};
    try {
        copy_replicas(output, inputs, spec, stored, target, exists, result);
    } catch (const std::exception& e) {
        // A failed read or write (an input that cannot be opened, a full disk) leaves no lock
        // and no half-made output: a new output goes, an existing one keeps the replicas copied
        // whole (a replica's status is written last), which the same merge run again completes.
        const bool stopped = dynamic_cast<const MergeStopped*>(&e) != nullptr;
        std::string what =
            "merging into '" + output + (stopped ? "' was stopped by a signal" : "' failed: " + std::string(e.what()));
        if (!exists) {
            std::filesystem::remove(output, ec);
            std::filesystem::remove(Archive::creation_marker(output), ec);
            if (!had_checkpoints) std::filesystem::remove_all(checkpoint_folder(output), ec);
            what += "; the new '" + output + "' was removed";
        } else {
            what += "; '" + output + "' keeps what it held and the " + std::to_string(result.copied) +
                    (result.copied == 1 ? " replica" : " replicas") + " this merge copied whole before " +
                    (stopped ? "it stopped" : "the failure") + ": run the same merge again to copy the rest";
        }
        lock->release();
        if (stopped) throw MergeStopped(what);
        throw MergeFailed(what);
    }
    lock->release();
    return result;
}

}  // namespace jamsim
