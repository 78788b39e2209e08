#pragma once
#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

#include "jamsim/io/archive.hpp"
#include "jamsim/io/campaign_spec.hpp"

namespace jamsim {

/// How rank 0 reports progress.
struct ProgressOptions {
    bool terminal = false;        ///< redraw one line ('\r') instead of printing lines
    double interval_seconds = 10; ///< between plain lines (terminal: between redraws, 0.5 s)
};

/// A slice of a campaign: replicas with id % count == index (Slurm array tasks, say).
struct Shard {
    int index = 0;
    int count = 1;
    bool contains(std::int64_t replica) const { return replica % count == index; }
};

/// What the farm did (on rank 0; other ranks get their own counts).
struct FarmSummary {
    std::int64_t ran = 0, failed = 0, skipped = 0;
    double wall_seconds = 0.0;
    double io_seconds = 0.0;  ///< this rank's time inside archive writes
};

/// Run every replica of `spec` (in `shard`) whose status in `archive` is pending or running, over all
/// ranks of `comm`. Rank 0 hands out replicas longest-estimated-cost first, one at a time,
/// and computes too: it answers requests between the samples of its own replica, so no
/// rank idles while work remains. Each rank writes its own replicas to the archive; a
/// replica that throws is recorded as failed and the campaign goes on. Collective.
/// Runs the pending and interrupted replicas of the archive (and, with retry_failed, the
/// failed ones again), within `shard`.
FarmSummary run_farm(MPI_Comm comm, const CampaignSpec& spec, Archive& archive,
                     const ProgressOptions& progress, Shard shard = {}, bool retry_failed = false);

} // namespace jamsim
