#include "jamsim/campaign/farm.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <numeric>
#include <optional>

#include <filesystem>

#include "jamsim/campaign/stop_request.hpp"
#include "jamsim/io/checkpoint_file.hpp"
#include "jamsim/parallel/mpi.hpp"

namespace jamsim {

namespace {

constexpr int kTagRequest = 11;  // worker → rank 0: Report of the replica just finished
constexpr int kTagAssign = 12;   // rank 0 → worker: replica id, kNoMoreWork or kStop
constexpr int kTagStop = 13;     // rank 0 → worker, once: stop at the next checkpoint step
constexpr std::int64_t kNoMoreWork = -1, kStop = -2;

enum class Outcome : std::int64_t { Done = 0, Failed = 1, Interrupted = 2 };

/// What a worker tells rank 0 when it asks for work.
struct Report {
    std::int64_t replica;  ///< −1 on the first request
    Outcome outcome;
};

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string hms(double s) {
    if (!(s >= 0) || s > 1e7) return "--:--:--";
    const auto t = static_cast<long>(s + 0.5);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
    return buf;
}

/// Rank 0's bookkeeping: the queue, who is running what, the progress line.
class Dispatcher {
  public:
    Dispatcher(MPI_Comm comm, const CampaignSpec& spec, std::vector<std::int64_t> queue,
               std::int64_t already_done, const ProgressOptions& progress)
        : comm_(comm), spec_(spec), queue_(std::move(queue)),
          total_(static_cast<std::int64_t>(queue_.size()) + already_done), done_(already_done),
          progress_(progress), start_(Clock::now()), last_print_(start_) {
        for (auto id : queue_) cost_total_run_ += estimated_cost(spec_.replicas[id]);
        workers_active_ = mpi::size(comm) - 1;
        active_.assign(static_cast<std::size_t>(mpi::size(comm)), true);
    }

    /// Next replica for rank 0 itself, or −1.
    std::int64_t take() {
        check_stop();
        if (stopping_ || next_ >= queue_.size()) return -1;
        ++running_;
        return queue_[next_++];
    }

    void finished(std::int64_t replica, Outcome outcome) {
        --running_;
        if (outcome == Outcome::Interrupted) {
            ++interrupted_;
            StopRequest::request();  // one replica stopped: the whole run stops
        } else {
            ++(outcome == Outcome::Failed ? failed_ : done_);
            cost_done_ += estimated_cost(spec_.replicas[replica]);
        }
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
            MPI_Status st;
            mpi::check(MPI_Probe(MPI_ANY_SOURCE, kTagRequest, comm_, &st), "MPI_Probe");
            serve_one(st.MPI_SOURCE);
        }
        print(true);
    }

    std::int64_t failed() const { return failed_; }
    std::int64_t interrupted() const { return interrupted_; }

  private:
    void serve_one(int source) {
        Report r{};
        mpi::check(MPI_Recv(&r, sizeof r, MPI_BYTE, source, kTagRequest, comm_,
                            MPI_STATUS_IGNORE),
                   "MPI_Recv (work request)");
        if (r.replica >= 0) finished(r.replica, r.outcome);
        std::int64_t next = take();
        if (next < 0) {
            --workers_active_;
            active_[static_cast<std::size_t>(source)] = false;
            if (stopping_) next = kStop;
        }
        mpi::check(MPI_Send(&next, 1, MPI_INT64_T, source, kTagAssign, comm_),
                   "MPI_Send (assignment)");
    }

    void print(bool final_line) {
        const double elapsed = seconds_since(start_);
        const double every = progress_.terminal ? 0.5 : progress_.interval_seconds;
        if (!final_line && std::chrono::duration<double>(Clock::now() - last_print_).count() < every)
            return;
        last_print_ = Clock::now();
        const double remaining =
            cost_done_ > 0 ? elapsed * (cost_total_run_ - cost_done_) / cost_done_ : -1;
        const auto total = static_cast<long long>(total_);
        const long long pending = total - done_ - failed_ - running_;
        std::fprintf(stdout, "%s[%s] %lld/%lld done, %lld running, %lld failed, %lld pending | "
                             "elapsed %s | remaining ~%s%s",
                     progress_.terminal ? "\r" : "", spec_.name.c_str(),
                     static_cast<long long>(done_), total, static_cast<long long>(running_),
                     static_cast<long long>(failed_), pending, hms(elapsed).c_str(),
                     hms(remaining).c_str(),
                     progress_.terminal && !final_line ? "   " : "\n");
        std::fflush(stdout);
    }

    MPI_Comm comm_;
    const CampaignSpec& spec_;
    std::vector<std::int64_t> queue_;
    std::size_t next_ = 0;
    std::int64_t total_;  ///< replicas of this run's shard
    std::int64_t done_ = 0, failed_ = 0, running_ = 0, interrupted_ = 0;
    int workers_active_ = 0;
    std::vector<bool> active_;  ///< by rank: a worker not yet told that there is no more work
    bool stopping_ = false;
    double cost_total_run_ = 0, cost_done_ = 0;  ///< estimated costs of this run's queue
    ProgressOptions progress_;
    Clock::time_point start_, last_print_;
};

/// Run one replica (from its checkpoint, if it has one) and record it.
Outcome run_one(const CampaignSpec& spec, std::int64_t id, Archive& archive, int rank,
                const FarmOptions& options, const std::function<void()>& between,
                const std::function<bool()>& stop, FarmSummary& summary) {
    namespace fs = std::filesystem;
    const ReplicaParams& params = spec.replicas[static_cast<std::size_t>(id)];
    const auto t0 = Clock::now();
    double io = 0;
    auto timed = [&](auto&& f) {
        const auto a = Clock::now();
        f();
        io += seconds_since(a);
    };
    const std::string checkpoint = checkpoint_path(options.archive_path, id);
    std::optional<ReplicaState> resume;
    if (fs::exists(checkpoint)) timed([&] { resume = read_checkpoint(checkpoint, params); });
    std::optional<System> initial;
    if (options.initial_states && !resume) timed([&] { initial = options.initial_states->load(params, id); });
    timed([&] { archive.mark_running(id, rank); });
    auto last_save = Clock::now();
    const CheckpointPolicy policy{
        .due = [&] { return seconds_since(last_save) >= options.checkpoint_seconds; },
        .save =
            [&](const ReplicaState& state) {
                timed([&] {
                    write_checkpoint(checkpoint, params, state);
                    archive.write_progress(id, state.series,
                                           static_cast<double>(state.step) / static_cast<double>(std::max<std::int64_t>(state.steps, 1)));
                });
                last_save = Clock::now();
            },
        .stop = stop};
    Outcome outcome = Outcome::Done;
    std::shared_ptr<const ReplicaState> last_checkpoint;
    try {
        const ReplicaResult result = run_replica(
            params, RunContext{.after_sample = between, .checkpoints = &policy,
                               .resume = resume ? &*resume : nullptr,
                               .initial = initial ? &*initial : nullptr});
        timed([&] { archive.write_done(id, result, rank); });
        last_checkpoint = result.last_checkpoint;
    } catch (const h5::Error&) {
        throw;  // the archive itself is broken: stop
    } catch (const ReplicaInterrupted&) {
        outcome = Outcome::Interrupted;  // its state is saved; status stays "running"
    } catch (const std::exception& e) {
        outcome = Outcome::Failed;
        timed([&] { archive.write_failed(id, e.what(), seconds_since(t0), rank); });
    }
    if (outcome != Outcome::Interrupted) {  // finished: its checkpoint (and a .tmp left by a
        std::error_code ignored;             // kill during a write) is stale now
        fs::remove(checkpoint, ignored);
        fs::remove(checkpoint + ".tmp", ignored);
    }
    if (outcome == Outcome::Done && last_checkpoint)  // kept: a longer run continues from it
        timed([&] { write_checkpoint(checkpoint, params, *last_checkpoint, true); });
    summary.resumed += resume ? 1 : 0;
    summary.io_seconds += io;
    ++summary.ran;
    summary.failed += outcome == Outcome::Failed;
    summary.interrupted += outcome == Outcome::Interrupted;
    return outcome;
}

} // namespace

FarmSummary run_farm(MPI_Comm comm, const CampaignSpec& spec, Archive& archive,
                     const FarmOptions& options) {
    const int rank = mpi::rank(comm);
    const auto t0 = Clock::now();
    FarmSummary summary;
    if (rank == 0) {
        const auto status = archive.read_status();
        std::vector<std::int64_t> queue;
        std::int64_t done = 0;
        for (std::size_t r = 0; r < status.size(); ++r) {
            if (!options.shard.contains(static_cast<std::int64_t>(r))) continue;
            if (status[r] == ReplicaStatus::Pending || status[r] == ReplicaStatus::Running ||
                (options.retry_failed && status[r] == ReplicaStatus::Failed))
                queue.push_back(static_cast<std::int64_t>(r));
            else
                ++done;
        }
        summary.skipped = done;
        // Longest estimated cost first; ties in id order (deterministic).
        std::stable_sort(queue.begin(), queue.end(), [&](auto a, auto b) {
            return estimated_cost(spec.replicas[a]) > estimated_cost(spec.replicas[b]);
        });
        Dispatcher d(comm, spec, std::move(queue), done, options.progress);
        const std::function<void()> serve = [&d] { d.serve_pending(); };
        const std::function<bool()> stop = [&d] {
            d.check_stop();
            return d.stopping();
        };
        for (std::int64_t id = d.take(); id >= 0; id = d.take()) {
            const Outcome outcome = run_one(spec, id, archive, rank, options, serve, stop, summary);
            d.finished(id, outcome);
            d.serve_pending();
        }
        d.serve_until_workers_stop();
    } else {
        bool stop_seen = false;  // kTagStop received from rank 0
        const std::function<void()> poll = [&] {
            int flag = 0;
            if (stop_seen) return;
            mpi::check(MPI_Iprobe(0, kTagStop, comm, &flag, MPI_STATUS_IGNORE), "MPI_Iprobe (stop)");
            if (!flag) return;
            std::int64_t ignored = 0;
            mpi::check(MPI_Recv(&ignored, 1, MPI_INT64_T, 0, kTagStop, comm, MPI_STATUS_IGNORE),
                       "MPI_Recv (stop)");
            stop_seen = true;
        };
        const std::function<bool()> stop = [&] {
            poll();
            return stop_seen || StopRequest::requested();
        };
        Report report{-1, Outcome::Done};
        for (;;) {
            mpi::check(MPI_Send(&report, sizeof report, MPI_BYTE, 0, kTagRequest, comm),
                       "MPI_Send (work request)");
            std::int64_t id = kNoMoreWork;
            mpi::check(MPI_Recv(&id, 1, MPI_INT64_T, 0, kTagAssign, comm, MPI_STATUS_IGNORE),
                       "MPI_Recv (assignment)");
            if (id == kStop && !stop_seen) {  // rank 0 sent kTagStop first: take it
                std::int64_t ignored = 0;
                mpi::check(MPI_Recv(&ignored, 1, MPI_INT64_T, 0, kTagStop, comm, MPI_STATUS_IGNORE),
                           "MPI_Recv (stop)");
                stop_seen = true;
            }
            if (id < 0) break;
            const Outcome outcome = run_one(spec, id, archive, rank, options, poll, stop, summary);
            report = {id, outcome};
        }
    }
    summary.wall_seconds = seconds_since(t0);
    return summary;
}

} // namespace jamsim
