#pragma once
// The campaign lifecycle as functions with plain inputs and outputs: what rank 0 decides
// before a run (check_run: the campaign, its archive, growing or extending it, what is
// refused), the run over MPI ranks (run_campaign) and the merging of archives
// (merge_archives). The command line (src/app) parses arguments and prints what these return.
#include <mpi.h>

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "jamsim/archive/capacity.hpp"
#include "jamsim/campaign/farm.hpp"
#include "jamsim/campaign/run_checks.hpp"
#include "jamsim/spec/campaign_spec.hpp"

namespace jamsim {

/// Bad input or an archive that does not fit: one message (file, key or archive, value, what
/// is allowed or what to do); nothing was written. The command line exits with status 2.
struct CampaignRefused : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// What `jamsim run` was asked.
struct RunRequest {
    std::string spec_path;
    std::string output;    ///< overrides [campaign] output when not empty
    bool dry_run = false;  ///< check only: nothing is created, completed or removed
    int ranks = 1;         ///< the run's ranks (the archive's memory estimate)
    int node_ranks = 1;    ///< of those, on one node (the node's memory)
    std::int64_t max_replicas = kDefaultMaxReplicas;
    CapacityLimits limits;
};

/// What rank 0 found before any rank starts work.
struct RunDecision {
    std::string spec_text;      ///< the campaign file as read (every rank parses the same text)
    std::string output;         ///< the archive's path as MPI-IO is given it (symlinks resolved)
    bool output_given = false;  ///< -o gave it (rank 0: refusals name -o, not [campaign] output)
    OutputMode mode = OutputMode::Fresh;
    std::vector<std::int64_t> grow_source;  ///< Grow: the archive's id of each replica (−1: new)
    std::int64_t grow_kept = 0;             ///< Grow: replicas kept from the archive
    CapacityEstimate capacity;              ///< sizes and memory (the dry run prints them)
    bool sized = false;                     ///< `capacity` was estimated (the campaign was read)
    std::string error;                      ///< why the run is refused; "" when it may run
    std::string dry_run_refusal;            ///< dry run: the capacity check the run would fail
    std::vector<std::string> notes;         ///< what was done first (an interrupted growth finished)
    std::vector<std::string> warnings;      ///< advisories (run_checks.hpp), each "FILE: what"
};

/// Rank 0's checks (no collective calls): reads the campaign, sizes the archive and the
/// memory, completes or undoes a growth that a kill interrupted (not in a dry run), decides
/// whether the archive is new, resumed, extended or grown, and checks the checkpoints beside
/// it, the PETSc options, the [run] initial source and the archive's lock. Bad input is
/// `error`, never an exception.
RunDecision check_run(const RunRequest& request);

/// How run_campaign runs and what it says while it does.
struct RunSettings {
    std::string spec_path;  ///< names the run in the archive's lock
    ProgressOptions progress;
    Shard shard;
    bool retry_failed = false;
    double checkpoint_seconds = 300.0;
    /// Rank 0's lines on what the run does before its progress lines (may be empty).
    std::function<void(const std::string&)> say;
};

/// What a run did: counts summed over ranks (on rank 0; other ranks their own).
struct RunOutcome {
    enum class End { finished, interrupted, refused };
    End end = End::finished;
    std::string refusal;  ///< refused: why (another run holds the archive, creating it failed)
    std::int64_t ran = 0, failed = 0, resumed = 0, skipped = 0;
    std::int64_t interrupted = 0;  ///< replicas that saved their state at a checkpoint step
    double wall_seconds = 0;       ///< rank 0's
    double io_share = 0;           ///< archive writes over rank time, all ranks (rank 0)
};

/// The run of `spec` (every rank; `decision` broadcast from rank 0's check_run): takes the
/// archive's lock, extends or grows the archive when decided, creates or opens it, runs the
/// farm and stamps it. A failure of a collective step throws on the ranks that saw it (the
/// caller aborts the job); a creation that failed on any rank is `refused` on every rank,
/// with no partial file left.
RunOutcome run_campaign(MPI_Comm comm, const CampaignSpec& spec, const RunDecision& decision,
                        const RunSettings& settings);

/// A merge that failed midway (an input unreadable, the disk full): says what was kept.
struct MergeFailed : std::runtime_error {
    using std::runtime_error::runtime_error;
};
/// A merge stopped by a signal (Ctrl-C, SIGTERM) between two replicas: says what was kept.
struct MergeStopped : MergeFailed {
    using MergeFailed::MergeFailed;
};

/// What merge_archives did.
struct MergeOutcome {
    std::int64_t copied = 0;      ///< replicas copied into the output
    std::size_t replicas = 0;     ///< the output campaign's replicas
    bool union_campaign = false;  ///< the output's campaign is the union of the inputs' sweeps
};

/// Shards of one campaign, or archives of campaigns that differ only in their sweeps, into
/// `output` (created, or completed if it exists; one process): the output's campaign is then
/// the union of their replicas, matched by identity (parameters and seed). Throws
/// CampaignRefused (nothing written) for inputs that cannot be merged, and MergeFailed when a
/// read or write fails midway (the lock released; a new output removed, an existing one holding
/// whole replicas only).
MergeOutcome merge_archives(const std::string& output, const std::vector<std::string>& inputs);

}  // namespace jamsim
