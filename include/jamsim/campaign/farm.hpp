#pragma once
#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

#include "jamsim/archive/archive.hpp"
#include "jamsim/spec/campaign_spec.hpp"
#include "jamsim/io/initial_states.hpp"

namespace jamsim {

/// How rank 0 reports progress.
struct ProgressOptions {
    bool terminal = false;         ///< redraw one line ('\r') instead of printing lines
    double interval_seconds = 10;  ///< between plain lines (terminal: between redraws, 0.5 s)
};

/// A slice of a campaign (Slurm array tasks, say): the chains with chain % count == index,
/// chains numbered as chains_of numbers them (campaign/scheduler.hpp: by their first
/// replica's id). A rate ladder is one chain and so never spans shards; without ladders
/// every replica is a chain of its own and a shard holds the replicas with id % count == index.
struct Shard {
    int index = 0;
    int count = 1;
    bool contains(std::int64_t chain) const { return chain % count == index; }
};

/// How the farm runs a campaign.
struct FarmOptions {
    ProgressOptions progress;
    Shard shard;
    bool retry_failed = false;  ///< run failed replicas again
    /// The archive's path: checkpoints live beside it (io/checkpoint_file.hpp).
    std::string archive_path;
    /// Save a running replica's state at its first checkpoint step after this many seconds
    /// since its last save (0: at every checkpoint step).
    double checkpoint_seconds = 300.0;
    /// [run] initial: the archive the replicas start from (nullptr: random positions).
    const InitialStates* initial_states = nullptr;
};

/// What the farm did (on rank 0; other ranks get their own counts).
struct FarmSummary {
    std::int64_t ran = 0, failed = 0, skipped = 0;
    std::int64_t interrupted = 0;  ///< stopped at a checkpoint step (StopRequest)
    std::int64_t resumed = 0;      ///< continued from a checkpoint
    double wall_seconds = 0.0;
    double io_seconds = 0.0;  ///< this rank's time inside archive writes
};

/// Run every replica of `spec` (in `options.shard`) whose status in `archive` is pending or
/// running (and, with retry_failed, failed), over all ranks of `comm`. Rank 0 hands out
/// replicas one at a time, longest remaining critical path first (campaign/scheduler.hpp:
/// the replica's estimated cost plus its rate ladder's later replicas'), and computes too: it
/// answers requests between the samples of its own replica, so no rank idles while work
/// remains.
/// Each rank writes its own replicas to the archive; a replica that throws is recorded as
/// failed and the campaign goes on. A replica with a checkpoint continues from it; running
/// replicas save their state at checkpoint steps (beside the archive, rows into it). When a
/// StopRequest arrives on any rank, every running replica saves its state at its next
/// checkpoint step and stops, and no new replica starts. Collective.
FarmSummary run_farm(MPI_Comm comm, const CampaignSpec& spec, Archive& archive, const FarmOptions& options);

}  // namespace jamsim
