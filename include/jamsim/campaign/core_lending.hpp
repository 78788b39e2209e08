#pragma once
// Cores lent between the ranks of a node. A rank of a campaign owns the cores of its threads
// (--threads T). When it has no replica to run (its ladder's next replica waits for another,
// or the campaign's work is all handed out), it parks: it waits without spinning, and its
// cores go to a rank of the same node that still runs a replica, the longest remaining
// critical path first, which raises its replica's threads at its next sample. The bits of a
// replica do not depend on its threads (README "Threads inside a replica"), so lending
// changes only when a replica ends, never what it computes.
#include <mpi.h>

#include <cstdint>
#include <vector>

namespace jamsim {

/// A rank's cores.
struct RankCores {
    std::int64_t node = 0;  ///< which node (ranks that share memory share a node)
    int own = 1;            ///< its threads (--threads or OMP_NUM_THREADS)
    /// The most threads it may run without sharing a core: the CPUs of its affinity mask,
    /// or `own` when OpenMP binds its threads (OMP_PROC_BIND), since lent threads would then
    /// be bound onto its own cores.
    int most = 1;
};

/// What a rank does now.
struct RankWork {
    bool running = false;  ///< runs a replica
    double priority = 0;   ///< its replica's remaining critical path (campaign/scheduler.hpp)
    int useful = 1;        ///< threads past which its replica gains nothing (the pair loop's blocks)
};

/// Threads for every rank: an idle rank keeps its own (it runs nothing); a running rank gets
/// its own plus the own threads of its node's idle ranks, handed to the node's running ranks
/// in order of priority (then lowest rank), each up to min(most, useful) and never below its own.
/// Deterministic.
std::vector<int> lend_cores(const std::vector<RankCores>& cores, const std::vector<RankWork>& work);

/// This rank's cores (collective over `comm`: ranks that share memory are one node), on
/// every rank.
std::vector<RankCores> gather_rank_cores(MPI_Comm comm);

/// The pair loop's blocks for N disks: more threads than this gain nothing.
int useful_threads(std::int64_t n);

/// Wait for `request` without keeping a core busy (MPI's own waits spin): test, then sleep,
/// 50 µs at first and doubling to 10 ms. `what` names the call in an error.
void park_until_complete(MPI_Request& request, const char* what);

} // namespace jamsim
