#pragma once
// Which replica runs next. Pure (no MPI, no files): the farm's Dispatcher (rank 0) drives a
// Scheduler with the replicas' estimated costs, and simulate_schedule drives the very same
// Scheduler with per-replica seconds to predict a campaign's wall time (the dry run, jamsim
// plan). The order never changes a replica's bits: only when and where it runs.
#include <cstdint>
#include <set>
#include <utility>
#include <vector>

#include "jamsim/parallel/thread_scaling.hpp"

namespace jamsim {

/// The chains of a campaign: replicas linked by `predecessor` (a rate ladder: each replica
/// starts from its predecessor's end state; −1: none). Every replica is in one chain; a
/// replica without predecessor (and without successor) is a chain of its own.
struct Chains {
    std::vector<std::int64_t> chain_of;              ///< per replica: the index of its chain
    std::vector<std::vector<std::int64_t>> members;  ///< per chain: its replicas, first to last
};

/// Chains numbered in the order of their first replica's id; without ladders (`predecessor`
/// empty) chain k is replica k. Throws std::invalid_argument for a predecessor out of range
/// or a cycle.
Chains chains_of(const std::vector<std::int64_t>& predecessor, std::size_t replicas);

/// How a replica ended, for the scheduler.
enum class Ended { Done, Failed, Interrupted };

/// The farm's order: among the replicas that can start now (no predecessor, or a predecessor
/// done), the one with the longest remaining critical path (its cost plus the costs of
/// everything queued after it in its chain), then the longest cost, then the lowest id. A
/// campaign's makespan then approaches max(total work / cores, longest chain). Deterministic:
/// the same calls give the same answers.
class Scheduler {
  public:
    /// How a replica stood before this run.
    enum class Before : std::int8_t { Open, Done, Failed };

    /// `cost`: every replica's estimated cost (any unit > 0; only the order counts);
    /// `predecessor`: as in chains_of; `queue`: the replicas this run runs; `before`: every
    /// replica's standing (a queued replica's successors wait for it whatever it says). A
    /// queued replica whose predecessor failed before (and is not queued) fails at once.
    Scheduler(std::vector<double> cost, std::vector<std::int64_t> predecessor, const std::vector<std::int64_t>& queue,
              const std::vector<Before>& before);

    /// The ready replica of highest priority, now counted as running; −1 when none is ready.
    std::int64_t take();
    /// A running replica ended. Done: its successors may start. Failed: its queued
    /// successors fail with it (see take_failed). Interrupted: it stays unfinished.
    void finished(std::int64_t id, Ended how);
    /// Replicas failed because their predecessor failed, each with that predecessor, since
    /// the last call (in chain order).
    std::vector<std::pair<std::int64_t, std::int64_t>> take_failed();

    /// A queued replica waits for one that runs now.
    bool may_become_ready() const { return blocked_ > 0 && running_ > 0; }
    bool idle() const { return ready_.empty() && running_ == 0; }
    std::int64_t running() const { return running_; }
    std::int64_t queued() const { return static_cast<std::int64_t>(ready_.size()) + blocked_; }
    /// A queued replica's remaining critical path (its cost plus its queued successors').
    double critical_path(std::int64_t id) const { return path_[static_cast<std::size_t>(id)]; }

  private:
    struct Order {
        const Scheduler* s;
        bool operator()(std::int64_t a, std::int64_t b) const;
    };
    enum class State : std::int8_t { Outside, Blocked, Ready, Running, Done, Failed };
    void fail_successors(std::int64_t id);
    State& state(std::int64_t id) { return state_[static_cast<std::size_t>(id)]; }

    std::vector<double> cost_, path_;
    std::vector<std::int64_t> predecessor_;
    std::vector<std::vector<std::int64_t>> successors_;
    std::vector<State> state_;
    std::set<std::int64_t, Order> ready_{Order{this}};
    std::int64_t blocked_ = 0, running_ = 0;
    std::vector<std::pair<std::int64_t, std::int64_t>> failed_;
};

/// How many times faster a replica runs on T threads than on one: Amdahl's law,
/// 1 / (f + (1 − f) / T'), with T' = min(T, useful_threads(kernel, N)) and the serial
/// fraction f of its kernel by N, fitted to one run on a 16-core Xeon (tests/bench/README.md:
/// tests/bench/scaling.sh for the pair loop and CG, "CD0 on threads" for the
/// contact solve), interpolated in log N and held beyond the ends:
///  - pair_loop (RD0): 2.46× at N = 16384 on 16 threads (4 blocks), 9.50× at 65536 and 9.57×
///    at 262144, which are f = 0.21, 0.046 and 0.045, rounded up to 0.21, 0.05 and 0.045;
///  - minimiser (CG): 2.83×, 2.91× and 3.49× at N = 16384 on 4, 8 and 16 threads (4 blocks),
///    3.10×, 4.48× and 6.91× at 65536: f = 0.10 at both (1.82× to 6.40× on 2 to 16 threads
///    at 65536, where 2 threads measured 2.38×);
///  - contact_solve (CD0): about 1.38× at N = 16384 and 1.46× at 65536 on 2 threads (medians,
///    tests/bench/cd0_threads.md, the 2-core VM): f = 0.45 and 0.37, on at most 2
///    threads (the factor splits its elimination tree in two; the older code gained nothing
///    past 2 on the 16-core Xeon).
/// Below 4096 disks the kernel's loops run on one thread (f = 1). `serial_fraction` >= 0
/// replaces the tables with one fraction for every N and kernel (the thread caps stay).
struct SpeedupModel {
    double serial_fraction = -1;
    double fraction(ThreadScaling kernel, std::int64_t n) const;
    double speedup(ThreadScaling kernel, std::int64_t n, int threads) const;
};

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

/// The most threads a replica of N disks gains from: the pair loop's blocks (it shares out
/// whole blocks: 4 at N = 16384, 16 at 65536, 32 from 131072), and 2 for the contact solve
/// from 4096 disks on (its solve's two threads).
int useful_threads(ThreadScaling kernel, std::int64_t n);

/// The ranks in the order the farm hands out its first replicas: the first rank of every
/// node, then the second of every node, and so on (nodes in order of their first rank), so
/// that the longest chains start on different nodes and each has idle ranks beside it to
/// lend it cores when the short work ends.
std::vector<int> spread_over_nodes(const std::vector<RankCores>& cores);

/// One replica for simulate_schedule.
struct SimulatedReplica {
    double cost = 0;     ///< what the farm orders by (its estimated cost)
    double seconds = 0;  ///< its run time on one thread
    double speedup = 1;  ///< how many times faster it runs on the run's threads
    // For a run with cores lent (SimulatedLending): its disks and the seconds that threads
    // do not shorten (its samples); on T threads it takes
    // (seconds − serial) / SpeedupModel::speedup(kernel, n, T) + serial.
    std::int64_t n = 0;
    double serial = 0;
    ThreadScaling kernel = ThreadScaling::pair_loop;  ///< its model's (ModelInfo::thread_scaling)
};

/// A replica's seconds on `threads`: its `serial` part as it is, the rest sped up by `model`.
double seconds_on_threads(const SimulatedReplica& r, const SpeedupModel& model, int threads);

/// Cores lent by ranks without work (campaign/core_lending.hpp), for simulate_schedule:
/// ranks [k·ranks_per_node, (k+1)·ranks_per_node) share node k, every rank may use the whole
/// node's cores, free ranks take work in spread_over_nodes order, and a replica's threads
/// follow lend_cores at every start and end.
struct SimulatedLending {
    int ranks_per_node = 1;
    SpeedupModel model;
};

/// A simulated run of a campaign on `workers` ranks of `threads` threads each.
struct SimulatedRun {
    double makespan = 0;              ///< seconds until the last replica ends
    double work = 0;                  ///< total one-thread seconds (core-seconds at full efficiency)
    double critical_path = 0;         ///< the longest chain's seconds at the run's threads
    std::int64_t longest_chain = -1;  ///< its index (chains_of)
    double bound = 0;                 ///< max(work / cores, critical_path): no schedule beats it
    double idle_core_seconds = 0;     ///< cores × makespan − Σ replica seconds × threads
    std::int64_t chains = 0;          ///< independent chains: at most this many replicas run at once
};

/// A discrete-event run of the Scheduler: every free worker (lowest index first) takes the
/// scheduler's next replica and holds it for seconds / speedup; completions at one instant
/// are all reported before the free workers take new work. Every replica is queued, none
/// done before. With `lending`, a replica's speed changes whenever the cores lent change.
SimulatedRun simulate_schedule(const std::vector<SimulatedReplica>& replicas,
                               const std::vector<std::int64_t>& predecessor, int workers, int threads,
                               const SimulatedLending* lending = nullptr);

}  // namespace jamsim
