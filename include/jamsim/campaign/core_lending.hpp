#pragma once
// Cores lent between the ranks of a node. A rank of a campaign owns the cores of its threads
// (--threads T). When it has no replica to run (its ladder's next replica waits for another,
// or the campaign's work is all handed out), it parks: it waits without spinning, and its
// cores go to a rank of the same node that still runs a replica, the longest remaining
// critical path first, which raises its replica's threads at its next sample. The bits of a
// replica do not depend on its threads (slurm/README.md, "Threads inside a replica"), so lending
// changes only when a replica ends, never what it computes. Who gets which cores is decided
// by lend_cores (campaign/scheduler.hpp), which the wall-time simulation uses too.
#include <mpi.h>

#include <chrono>
#include <functional>
#include <vector>

#include "jamsim/campaign/scheduler.hpp"

namespace jamsim {

/// This rank's cores (collective over `comm`: ranks that share memory are one node), on
/// every rank.
std::vector<RankCores> gather_rank_cores(MPI_Comm comm);

/// Wait until `ready()` without keeping a core busy (MPI's own waits spin): ask, then sleep,
/// 50 µs at first and doubling up to `longest`.
void park_until(const std::function<bool()>& ready, std::chrono::microseconds longest);

/// park_until `request` completes, sleeping up to 10 ms. `what` names the call in an error.
void park_until_complete(MPI_Request& request, const char* what);

}  // namespace jamsim
