#include "jamsim/campaign/farm.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <numeric>
#include <optional>
#include <thread>

#include "jamsim/campaign/core_lending.hpp"
#include "jamsim/campaign/costs.hpp"
#include "jamsim/campaign/scheduler.hpp"
#include "jamsim/campaign/stop_request.hpp"
#include "jamsim/campaign/throughput.hpp"
#include "jamsim/parallel/mpi.hpp"
#include "jamsim/parallel/threads.hpp"
#include "jamsim/run/model_registry.hpp"
#include "run_one.hpp"

namespace jamsim {

namespace {

constexpr int kTagRequest = 11;   // worker → rank 0: Report of the replica just finished
constexpr int kTagAssign = 12;    // rank 0 → worker: Assignment
constexpr int kTagStop = 13;      // rank 0 → worker, once: stop at the next checkpoint step
constexpr int kTagThreads = 14;   // rank 0 → worker: threads for its running replica (cores lent)
constexpr int kTagFarmOver = 15;  // rank 0 → every worker, at the end: leave the farm
constexpr std::int64_t kNoMoreWork = -1, kStop = -2;

/// What a worker tells rank 0 when it asks for work.
struct Report {
    std::int64_t replica;  ///< −1 on the first request
    Outcome outcome;
};

/// Rank 0's answer to a request.
struct Assignment {
    std::int64_t replica = kNoMoreWork;  ///< replica id, kNoMoreWork or kStop
    std::int64_t threads = 1;            ///< threads to start it on (its own, or more when lent)
    std::int64_t updates = 0;            ///< kTagThreads messages sent to this worker so far
};

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string hms(double s) {
    if (!(s >= 0) || s > 1e7) return "--:--:--";
    const auto t = static_cast<long>(s + 0.5);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
    return buf;
}

/// The scheduler of this run's queue: every replica's estimated cost, its predecessor, and
/// how the archive says it stands.
Scheduler make_scheduler(const CampaignSpec& spec, const std::vector<std::int64_t>& queue,
                         const std::vector<ReplicaStatus>& status) {
    std::vector<double> cost(spec.replicas.size());
    std::vector<Scheduler::Before> before(spec.replicas.size(), Scheduler::Before::Open);
    for (std::size_t r = 0; r < cost.size(); ++r) {
        cost[r] = estimated_cost(spec.replicas[r]);
        if (status[r] == ReplicaStatus::Done) before[r] = Scheduler::Before::Done;
        if (status[r] == ReplicaStatus::Failed) before[r] = Scheduler::Before::Failed;
    }
    return Scheduler(std::move(cost), spec.predecessor, queue, before);
}

/// Rank 0's bookkeeping: the scheduler (which replica next), who is running what, the
/// progress line. A replica of a rate ladder is ready once its predecessor is done; a worker
/// asking while nothing is ready but something may become ready waits (its request is
/// answered later); a replica whose predecessor failed fails too.
class Dispatcher {
  public:
    Dispatcher(MPI_Comm comm, const CampaignSpec& spec, const std::vector<std::int64_t>& queue,
               std::int64_t already_done, const std::vector<ReplicaStatus>& status,
               std::function<void(std::int64_t, const std::string&)> fail, const ProgressOptions& progress,
               std::vector<RankCores> cores)
        : comm_(comm), spec_(spec), scheduler_(make_scheduler(spec, queue, status)), fail_(std::move(fail)),
          total_(static_cast<std::int64_t>(queue.size()) + already_done), done_(already_done), progress_(progress),
          cost_(spec.replicas.size(), 0.0), start_(Clock::now()), last_print_(start_) {
        for (const std::int64_t id : queue) {
            const ReplicaParams& p = spec_.replicas[static_cast<std::size_t>(id)];
            cost_[static_cast<std::size_t>(id)] = estimated_cost(p);
            GroupLeft& group = cost_left_[cost_group(p)];
            group.params = &p;
            group.cost += cost_[static_cast<std::size_t>(id)];
        }
        workers_active_ = mpi::size(comm) - 1;
        active_.assign(static_cast<std::size_t>(mpi::size(comm)), true);
        cores_ = std::move(cores);
        replica_of_.assign(cores_.size(), -1);
        updates_sent_.assign(cores_.size(), 0);
        started_.assign(cores_.size(), Clock::now());
        for (const RankCores& c : cores_) threads_.push_back(c.own);
        record_failures();  // replicas whose predecessor had failed before this run
    }

    /// Next replica for rank 0 itself, or −1 (waiting, serving requests, while a ladder's
    /// predecessor still runs elsewhere).
    std::int64_t take() {
        for (;;) {
            check_stop();
            if (stopping_) return -1;
            const std::int64_t first = own_first_;  // chosen for rank 0 in the first round
            own_first_ = -1;
            if (const std::int64_t id = first >= 0 ? first : take_ready(); id >= 0) {
                replica_of_[0] = id;
                started_[0] = Clock::now();
                rebalance(-1);
                set_kernel_threads(threads_[0]);  // (unchanged by rebalance when it is its own)
                return id;
            }
            if (!may_become_ready()) return -1;
            serve_blocking();
        }
    }

    /// `replica`, run by `rank`, ended.
    void finished(std::int64_t replica, Outcome outcome, int rank) {
        --running_;
        replica_of_[static_cast<std::size_t>(rank)] = -1;
        const double wall = seconds_since(started_[static_cast<std::size_t>(rank)]);
        if (outcome == Outcome::Interrupted) {
            ++interrupted_;
            scheduler_.finished(replica, Ended::Interrupted);
            StopRequest::request();  // one replica stopped: the whole run stops
        } else {
            ++(outcome == Outcome::Failed ? failed_ : done_);
            scheduler_.finished(replica, outcome == Outcome::Failed ? Ended::Failed : Ended::Done);
            ended(replica);
            if (outcome == Outcome::Done) throughput_.add(spec_.replicas[replica], wall);
            record_failures();
        }
        wake_waiting();
        rebalance(-1);
        print(false);
    }

    /// Once a stop is requested: tell every worker (kTagStop), start nothing new.
    void check_stop() {
        if (stopping_ || !StopRequest::requested()) return;
        stopping_ = true;
        const std::int64_t stop = kStop;
        for (int w = 1; w < mpi::size(comm_); ++w)  // workers that have not been let go
            if (active_[static_cast<std::size_t>(w)])
                mpi::check(MPI_Send(&stop, 1, MPI_INT64_T, w, kTagStop, comm_), "MPI_Send (stop)");
        wake_waiting();
    }
    bool stopping() const { return stopping_; }

    /// Answer every pending request without blocking (called between samples).
    void serve_pending() {
        check_stop();
        int flag = 1;
        while (workers_active_ > 0) {
            MPI_Status st;
            mpi::check(MPI_Iprobe(MPI_ANY_SOURCE, kTagRequest, comm_, &flag, &st), "MPI_Iprobe");
            if (!flag) break;
            serve_one(st.MPI_SOURCE);
        }
        print(false);
    }

    /// Serve until every worker has been told to stop (rank 0 has no work left).
    void serve_until_workers_stop() {
        while (workers_active_ > 0) {
            wake_waiting();
            if (workers_active_ == 0) break;
            serve_blocking();
        }
        print(true);
    }

    std::int64_t failed() const { return failed_; }
    std::int64_t interrupted() const { return interrupted_; }

  private:
    /// Record the replicas failed because their predecessor failed.
    void record_failures() {
        for (const auto& [id, before] : scheduler_.take_failed()) {
            ++failed_;
            ended(id);
            fail_(id, "its predecessor in the rate ladder, replica " + std::to_string(before) + ", failed");
        }
    }

    /// The queued replica to start now, by the scheduler's order (−1 if none is ready).
    std::int64_t take_ready() {
        const std::int64_t id = scheduler_.take();
        running_ += id >= 0;
        return id;
    }

    /// Something queued may still become ready: a replica runs that could be a predecessor.
    bool may_become_ready() const { return scheduler_.may_become_ready(); }

    /// Wait for the next request without keeping the core busy (MPI_Probe spins), so that
    /// an idle rank 0 lends its core too: probe, then sleep 50 µs doubling to 1 ms.
    void serve_blocking() { serve_one(wait_for_request()); }

    /// The rank of the next request, waited for parked.
    int wait_for_request() {
        MPI_Status st;
        park_until(  // answers within 1 ms
            [&] {
                int flag = 0;
                mpi::check(MPI_Iprobe(MPI_ANY_SOURCE, kTagRequest, comm_, &flag, &st), "MPI_Iprobe");
                return flag != 0;
            },
            std::chrono::microseconds(1000));
        return st.MPI_SOURCE;
    }

    void reply(int worker, std::int64_t next) {
        const auto w = static_cast<std::size_t>(worker);
        if (next < 0) {
            --workers_active_;
            active_[w] = false;
            if (stopping_) next = kStop;
        } else {
            replica_of_[w] = next;
            started_[w] = Clock::now();
        }
        rebalance(worker);  // the worker's own threads go in the assignment
        const Assignment a{.replica = next, .threads = threads_[w], .updates = updates_sent_[w]};
        mpi::check(MPI_Send(&a, sizeof a, MPI_BYTE, worker, kTagAssign, comm_), "MPI_Send (assignment)");
    }

    /// Share the idle ranks' cores among the running ranks of their node (lend_cores) and
    /// tell each running rank whose threads change: rank 0 at once (it is between samples or
    /// replicas), a worker by a kTagThreads message that it takes at its next sample; `assigned`
    /// (a worker being sent its replica) gets its threads in the assignment instead.
    void rebalance(int assigned) {
        if (in_first_round_) return;  // once, at its end
        std::vector<RankWork> work(cores_.size());
        for (std::size_t r = 0; r < cores_.size(); ++r)
            if (const std::int64_t id = replica_of_[r]; id >= 0) {
                const ReplicaParams& p = spec_.replicas[static_cast<std::size_t>(id)];
                work[r] = {.running = true,
                           .priority = scheduler_.critical_path(id),
                           .useful = useful_threads(model_of(p).thread_scaling, p.n)};
            }
        const std::vector<int> threads = lend_cores(cores_, work);
        for (std::size_t r = 0; r < cores_.size(); ++r) {
            if (threads[r] == threads_[r]) continue;
            threads_[r] = threads[r];
            if (!work[r].running) continue;  // idle: its next replica comes with its threads
            note_lending(static_cast<int>(r), replica_of_[r], threads[r]);
            if (r == 0) {
                set_kernel_threads(threads[r]);
            } else if (static_cast<int>(r) != assigned) {
                const std::int64_t n = threads[r];
                mpi::check(MPI_Send(&n, 1, MPI_INT64_T, static_cast<int>(r), kTagThreads, comm_), "MPI_Send (threads)");
                ++updates_sent_[r];
            }
        }
    }

    /// One line when a running replica's threads change through lending.
    void note_lending(int rank, std::int64_t replica, int threads) {
        const int own = cores_[static_cast<std::size_t>(rank)].own;
        std::fprintf(stdout, "[%s] replica %lld (rank %d) now on %d thread%s%s\n", spec_.name.c_str(),
                     static_cast<long long>(replica), rank, threads, threads == 1 ? "" : "s",
                     threads > own ? (", " + std::to_string(threads - own) + " lent by idle ranks of its node").c_str()
                                   : ", its own");
        std::fflush(stdout);
    }

    void serve_one(int source) {
        Report r{};
        mpi::check(MPI_Recv(&r, sizeof r, MPI_BYTE, source, kTagRequest, comm_, MPI_STATUS_IGNORE),
                   "MPI_Recv (work request)");
        if (r.replica >= 0) finished(r.replica, r.outcome, source);
        answer(source);
    }

    /// Give `source` its next replica, or let it wait for one, or let it go.
    void answer(int source) {
        check_stop();
        const std::int64_t next = stopping_ ? -1 : take_ready();
        if (next < 0 && !stopping_ && may_become_ready()) {
            waiting_.push_back(source);  // answered when a predecessor finishes
            return;
        }
        reply(source, next);
    }

  public:
    /// The first requests (every worker asks once at start), answered in spread_over_nodes
    /// order, rank 0 in its place: the longest chains start on different nodes, where idle
    /// ranks can later lend them cores. The threads are shared out once, at the end.
    void first_round() {
        in_first_round_ = true;
        for (int asked = 1; asked < mpi::size(comm_); ++asked) {  // (first requests carry no replica)
            const int source = wait_for_request();
            Report r{};
            mpi::check(MPI_Recv(&r, sizeof r, MPI_BYTE, source, kTagRequest, comm_, MPI_STATUS_IGNORE),
                       "MPI_Recv (work request)");
        }
        for (const int rank : spread_over_nodes(cores_)) {
            if (rank != 0) {
                answer(rank);
            } else if (check_stop(), !stopping_) {
                own_first_ = take_ready();
                if (own_first_ >= 0) replica_of_[0] = own_first_;
            }
        }
        in_first_round_ = false;
        rebalance(-1);
    }

  private:
    /// Answer the waiting workers that can be answered now.
    void wake_waiting() {
        for (std::size_t k = 0; k < waiting_.size();) {
            const std::int64_t next = stopping_ ? -1 : take_ready();
            if (next < 0 && !stopping_ && may_become_ready()) return;
            reply(waiting_[k], next);
            waiting_.erase(waiting_.begin() + static_cast<std::ptrdiff_t>(k));
        }
    }

    void print(bool final_line) {
        const double elapsed = seconds_since(start_);
        const double every = progress_.terminal ? 0.5 : progress_.interval_seconds;
        if (!final_line && std::chrono::duration<double>(Clock::now() - last_print_).count() < every) return;
        last_print_ = Clock::now();
        const bool measured = throughput_.measured();
        const double remaining = remaining_seconds();
        const auto total = static_cast<long long>(total_);
        const long long pending = total - done_ - failed_ - running_ - interrupted_;
        // Replicas stopped by a signal have saved their state: "interrupted", not "pending".
        const std::string running = interrupted_ > 0 ? std::to_string(running_) + " running, " +
                                                           std::to_string(interrupted_) + " interrupted (saved)"
                                                     : std::to_string(running_) + " running";
        std::fprintf(stdout,
                     "%s[%s] %lld/%lld done, %s, %lld failed, %lld pending | "
                     "elapsed %s | remaining ~%s%s%s",
                     progress_.terminal ? "\r" : "", spec_.name.c_str(), static_cast<long long>(done_), total,
                     running.c_str(), static_cast<long long>(failed_), pending, hms(elapsed).c_str(),
                     hms(remaining).c_str(), measured || final_line ? "" : " (nominal)",
                     progress_.terminal && !final_line ? "   " : "\n");
        std::fflush(stdout);
    }

    /// A replica of this run's queue is done or failed: its cost is no longer left.
    void ended(std::int64_t id) {
        double& cost = cost_[static_cast<std::size_t>(id)];
        const ReplicaParams& p = spec_.replicas[static_cast<std::size_t>(id)];
        cost_left_[cost_group(p)].cost -= cost;
        cost = 0;  // counted once
    }

    /// Seconds left, without jumps as replicas end: each (model, N, phi) group's cost left at
    /// the throughput of its finished replicas (campaign/throughput.hpp: else of its model and
    /// N, its model, any; before the first, the nominal rate), less what each running replica
    /// has run by now; the work left over all ranks, or the longest remaining chain on one
    /// rank, whichever is larger. O(groups + ranks) per call. (One rate for every replica put
    /// a campaign whose groups differ in speed at what its fastest finished group would take.)
    double remaining_seconds() const {
        double left = 0, chain = 0;
        for (const auto& [key, group] : cost_left_)
            if (group.cost > 0) left += group.cost * throughput_.seconds_per_cost(*group.params);
        for (std::size_t r = 0; r < replica_of_.size(); ++r) {
            const std::int64_t id = replica_of_[r];
            if (id < 0) continue;
            const ReplicaParams& p = spec_.replicas[static_cast<std::size_t>(id)];
            const double part = std::min(cost_[static_cast<std::size_t>(id)] * throughput_.seconds_per_cost(p),
                                         seconds_since(started_[r]));
            left -= part;
            // The chain's queued replicas are of one model, N and phi (a rate ladder): its seconds
            // are its cost at this replica's rate.
            chain = std::max(chain, scheduler_.critical_path(id) * throughput_.seconds_per_cost(p) - part);
        }
        return std::max(std::max(left, 0.0) / static_cast<double>(mpi::size(comm_)), chain);
    }

    MPI_Comm comm_;
    const CampaignSpec& spec_;
    Scheduler scheduler_;                                         ///< the replicas not yet started, and which one next
    std::function<void(std::int64_t, const std::string&)> fail_;  ///< record a failure
    std::vector<int> waiting_;                                    ///< workers whose request waits for a ready replica
    std::int64_t total_;                                          ///< replicas of this run's shard
    std::int64_t done_ = 0, failed_ = 0, running_ = 0, interrupted_ = 0;
    int workers_active_ = 0;
    std::vector<bool> active_;  ///< by rank: a worker not yet told that there is no more work
    bool stopping_ = false;
    std::vector<RankCores> cores_;            ///< by rank: its node and cores
    std::vector<std::int64_t> replica_of_;    ///< by rank: the replica it runs, −1 when idle
    std::vector<int> threads_;                ///< by rank: its threads now
    std::vector<std::int64_t> updates_sent_;  ///< by rank: kTagThreads messages sent
    std::vector<Clock::time_point> started_;  ///< by rank: when its replica started
    bool in_first_round_ = false;
    std::int64_t own_first_ = -1;  ///< rank 0's replica chosen in the first round
    ProgressOptions progress_;
    struct GroupLeft {
        const ReplicaParams* params = nullptr;  ///< one of the group's replicas
        double cost = 0;                        ///< estimated cost of its replicas not ended
    };
    std::vector<double> cost_;                  ///< by replica: its estimated cost while queued and not ended, else 0
    std::map<CostGroup, GroupLeft> cost_left_;  ///< by (model, N, phi)
    Throughput throughput_;                     ///< of the replicas done in this run
    Clock::time_point start_, last_print_;
};

}  // namespace

FarmSummary run_farm(MPI_Comm comm, const CampaignSpec& spec, Archive& archive, const FarmOptions& options) {
    const int rank = mpi::rank(comm);
    const auto t0 = Clock::now();
    FarmSummary summary;
    const std::vector<RankCores> cores = gather_rank_cores(comm);  // collective
    const int own_threads = kernel_threads();
    std::vector<char> feeds(spec.replicas.size(), 0);  // replicas a rate ladder continues from
    for (const std::int64_t before : spec.predecessor)
        if (before >= 0) feeds[static_cast<std::size_t>(before)] = 1;
    if (rank == 0) {
        const auto status = archive.read_status();
        std::vector<std::int64_t> queue;
        std::int64_t done = 0;
        // A rate ladder is one chain: whole in one shard.
        const Chains chains = chains_of(spec.predecessor, spec.replicas.size());
        for (std::size_t r = 0; r < status.size(); ++r) {
            if (!options.shard.contains(chains.chain_of[r])) continue;
            if (status[r] == ReplicaStatus::Pending || status[r] == ReplicaStatus::Running ||
                (options.retry_failed && status[r] == ReplicaStatus::Failed))
                queue.push_back(static_cast<std::int64_t>(r));
            else
                ++done;
        }
        summary.skipped = done;
        Dispatcher d(
            comm, spec, queue, done, status,
            [&](std::int64_t id, const std::string& reason) {
                archive.write_failed(id, reason, 0.0, rank);
                ++summary.failed;
            },
            options.progress, cores);
        const std::function<void()> serve = [&d] { d.serve_pending(); };
        // Checkpoint steps serve the workers too (a protocol's stages sample rarely).
        const std::function<bool()> stop = [&d] {
            d.serve_pending();
            return d.stopping();
        };
        d.first_round();
        for (std::int64_t id = d.take(); id >= 0; id = d.take()) {
            const Outcome outcome = run_one(spec, id, feeds[static_cast<std::size_t>(id)] != 0, archive, rank, options,
                                            serve, stop, summary);
            d.finished(id, outcome, 0);
            d.serve_pending();
        }
        d.serve_until_workers_stop();
        // Every worker is parked (it lends its cores while it waits): let them go.
        for (int w = 1; w < mpi::size(comm); ++w)
            mpi::check(MPI_Send(nullptr, 0, MPI_BYTE, w, kTagFarmOver, comm), "MPI_Send (farm over)");
    } else {
        bool stop_seen = false;             // kTagStop received from rank 0
        std::int64_t updates_seen = 0;      // kTagThreads messages received
        const auto receive_threads = [&] {  // rank 0's next thread count, applied
            std::int64_t threads = 1;
            mpi::check(MPI_Recv(&threads, 1, MPI_INT64_T, 0, kTagThreads, comm, MPI_STATUS_IGNORE),
                       "MPI_Recv (threads)");
            ++updates_seen;
            set_kernel_threads(static_cast<int>(threads));
        };
        const auto take_threads = [&] {  // every thread count that has arrived
            for (int flag = 1;;) {
                mpi::check(MPI_Iprobe(0, kTagThreads, comm, &flag, MPI_STATUS_IGNORE), "MPI_Iprobe (threads)");
                if (!flag) return;
                receive_threads();
            }
        };
        const std::function<void()> poll = [&] {
            int flag = 0;
            take_threads();
            if (stop_seen) return;
            mpi::check(MPI_Iprobe(0, kTagStop, comm, &flag, MPI_STATUS_IGNORE), "MPI_Iprobe (stop)");
            if (!flag) return;
            std::int64_t ignored = 0;
            mpi::check(MPI_Recv(&ignored, 1, MPI_INT64_T, 0, kTagStop, comm, MPI_STATUS_IGNORE), "MPI_Recv (stop)");
            stop_seen = true;
        };
        const std::function<bool()> stop = [&] {
            poll();
            return stop_seen || StopRequest::requested();
        };
        Report report{-1, Outcome::Done};
        for (;;) {
            mpi::check(MPI_Send(&report, sizeof report, MPI_BYTE, 0, kTagRequest, comm), "MPI_Send (work request)");
            Assignment a;  // waited for parked: this rank's cores are lent meanwhile
            MPI_Request request = MPI_REQUEST_NULL;
            mpi::check(MPI_Irecv(&a, sizeof a, MPI_BYTE, 0, kTagAssign, comm, &request), "MPI_Irecv (assignment)");
            park_until_complete(request, "MPI_Test (assignment)");
            while (updates_seen < a.updates) receive_threads();  // sent for its last replica
            const std::int64_t id = a.replica;
            if (id >= 0) set_kernel_threads(static_cast<int>(a.threads));
            if (id == kStop && !stop_seen) {  // rank 0 sent kTagStop first: take it
                std::int64_t ignored = 0;
                mpi::check(MPI_Recv(&ignored, 1, MPI_INT64_T, 0, kTagStop, comm, MPI_STATUS_IGNORE), "MPI_Recv (stop)");
                stop_seen = true;
            }
            if (id < 0) break;
            const Outcome outcome = run_one(spec, id, feeds[static_cast<std::size_t>(id)] != 0, archive, rank, options,
                                            poll, stop, summary);
            report = {id, outcome};
        }
        MPI_Request over = MPI_REQUEST_NULL;  // parked until the whole farm is over
        mpi::check(MPI_Irecv(nullptr, 0, MPI_BYTE, 0, kTagFarmOver, comm, &over), "MPI_Irecv (farm over)");
        park_until_complete(over, "MPI_Test (farm over)");
    }
    set_kernel_threads(own_threads);
    summary.wall_seconds = seconds_since(t0);
    return summary;
}

}  // namespace jamsim
