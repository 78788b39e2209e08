#include "jamsim/campaign/scheduler.hpp"

#include "jamsim/neighbor/force_blocks.hpp"
#include "jamsim/parallel/threads.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <queue>
#include <stdexcept>
#include <string>
#include <tuple>

namespace jamsim {

namespace {

/// Each replica's successors (the replicas whose predecessor it is).
std::vector<std::vector<std::int64_t>> successors_of(const std::vector<std::int64_t>& predecessor,
                                                     std::size_t replicas) {
    std::vector<std::vector<std::int64_t>> next(replicas);
    if (predecessor.empty()) return next;
    if (predecessor.size() != replicas)
        throw std::invalid_argument("scheduler: " + std::to_string(predecessor.size()) + " predecessors for " +
                                    std::to_string(replicas) + " replicas");
    for (std::size_t r = 0; r < replicas; ++r) {
        const std::int64_t before = predecessor[r];
        if (before < -1 || before >= static_cast<std::int64_t>(replicas))
            throw std::invalid_argument("scheduler: replica " + std::to_string(r) + " has predecessor " +
                                        std::to_string(before) + ", not a replica");
        if (before >= 0) next[static_cast<std::size_t>(before)].push_back(static_cast<std::int64_t>(r));
    }
    return next;
}

/// Replicas with every predecessor before its successors: chain by chain, in the order of
/// their first replica's id. Throws for a cycle (replicas no first replica leads to).
std::vector<std::int64_t> chain_order(const std::vector<std::int64_t>& predecessor,
                                      const std::vector<std::vector<std::int64_t>>& next) {
    std::vector<std::int64_t> order;
    order.reserve(next.size());
    for (std::size_t r = 0; r < next.size(); ++r) {
        if (!predecessor.empty() && predecessor[r] >= 0) continue;
        std::size_t k = order.size();
        order.push_back(static_cast<std::int64_t>(r));
        for (; k < order.size(); ++k)  // breadth first: a chain's replicas first to last
            for (const std::int64_t s : next[static_cast<std::size_t>(order[k])]) order.push_back(s);
    }
    if (order.size() != next.size())
        throw std::invalid_argument("scheduler: the predecessors of " + std::to_string(next.size() - order.size()) +
                                    " replicas form a cycle");
    return order;
}

/// Per replica: its own length plus the longest path of the included replicas after it.
std::vector<double> remaining_paths(const std::vector<double>& length, const std::vector<std::int64_t>& order,
                                    const std::vector<std::vector<std::int64_t>>& next,
                                    const std::vector<char>& included) {
    std::vector<double> path(length.size(), 0.0);
    for (auto it = order.rbegin(); it != order.rend(); ++it) {
        const auto r = static_cast<std::size_t>(*it);
        double after = 0;
        for (const std::int64_t s : next[r])
            if (included[static_cast<std::size_t>(s)]) after = std::max(after, path[static_cast<std::size_t>(s)]);
        path[r] = length[r] + after;
    }
    return path;
}

}  // namespace

Chains chains_of(const std::vector<std::int64_t>& predecessor, std::size_t replicas) {
    const auto next = successors_of(predecessor, replicas);
    const auto order = chain_order(predecessor, next);
    Chains c;
    c.chain_of.assign(replicas, -1);
    for (const std::int64_t r : order) {
        const std::int64_t before = predecessor.empty() ? -1 : predecessor[static_cast<std::size_t>(r)];
        if (before < 0) {
            c.chain_of[static_cast<std::size_t>(r)] = static_cast<std::int64_t>(c.members.size());
            c.members.emplace_back();
        } else {
            c.chain_of[static_cast<std::size_t>(r)] = c.chain_of[static_cast<std::size_t>(before)];
        }
        c.members[static_cast<std::size_t>(c.chain_of[static_cast<std::size_t>(r)])].push_back(r);
    }
    return c;
}

bool Scheduler::Order::operator()(std::int64_t a, std::int64_t b) const {
    const auto i = static_cast<std::size_t>(a), j = static_cast<std::size_t>(b);
    return std::make_tuple(-s->path_[i], -s->cost_[i], a) < std::make_tuple(-s->path_[j], -s->cost_[j], b);
}

Scheduler::Scheduler(std::vector<double> cost, std::vector<std::int64_t> predecessor,
                     const std::vector<std::int64_t>& queue, const std::vector<Before>& before)
    : cost_(std::move(cost)), predecessor_(std::move(predecessor)) {
    const std::size_t n = cost_.size();
    if (before.size() != n)
        throw std::invalid_argument("scheduler: " + std::to_string(before.size()) + " standings for " +
                                    std::to_string(n) + " replicas");
    successors_ = successors_of(predecessor_, n);
    if (predecessor_.empty()) predecessor_.assign(n, -1);
    state_.assign(n, State::Outside);
    std::vector<char> queued(n, 0);
    for (const std::int64_t id : queue) {
        if (id < 0 || static_cast<std::size_t>(id) >= n || queued[static_cast<std::size_t>(id)])
            throw std::invalid_argument("scheduler: queued replica " + std::to_string(id) +
                                        " is not a replica, or queued twice");
        queued[static_cast<std::size_t>(id)] = 1;
        state(id) = State::Blocked;
    }
    blocked_ = static_cast<std::int64_t>(queue.size());
    path_ = remaining_paths(cost_, chain_order(predecessor_, successors_), successors_, queued);
    std::vector<std::int64_t> sorted = queue;
    std::sort(sorted.begin(), sorted.end());
    for (const std::int64_t id : sorted) {
        const std::int64_t pred = predecessor_[static_cast<std::size_t>(id)];
        if (state(id) != State::Blocked || (pred >= 0 && queued[static_cast<std::size_t>(pred)])) continue;
        const Before was = pred < 0 ? Before::Done : before[static_cast<std::size_t>(pred)];
        if (was == Before::Done) {
            state(id) = State::Ready;
            --blocked_;
            ready_.insert(id);
        } else if (was == Before::Failed) {
            state(id) = State::Failed;
            --blocked_;
            failed_.emplace_back(id, pred);
            fail_successors(id);
        }  // a predecessor neither done nor queued: it waits (may_become_ready says no)
    }
}

std::int64_t Scheduler::take() {
    if (ready_.empty()) return -1;
    const std::int64_t id = *ready_.begin();
    ready_.erase(ready_.begin());
    state(id) = State::Running;
    ++running_;
    return id;
}

void Scheduler::finished(std::int64_t id, Ended how) {
    if (id < 0 || static_cast<std::size_t>(id) >= state_.size() || state(id) != State::Running)
        throw std::logic_error("scheduler: replica " + std::to_string(id) + " finished but was not running");
    --running_;
    switch (how) {
    case Ended::Done:
        state(id) = State::Done;
        for (const std::int64_t s : successors_[static_cast<std::size_t>(id)])
            if (state(s) == State::Blocked) {
                state(s) = State::Ready;
                --blocked_;
                ready_.insert(s);
            }
        break;
    case Ended::Failed:
        state(id) = State::Failed;
        fail_successors(id);
        break;
    case Ended::Interrupted:
        state(id) = State::Outside;  // saved, unfinished: its successors keep waiting
        break;
    }
}

void Scheduler::fail_successors(std::int64_t id) {
    for (const std::int64_t s : successors_[static_cast<std::size_t>(id)])
        if (state(s) == State::Blocked) {
            state(s) = State::Failed;
            --blocked_;
            failed_.emplace_back(s, id);
            fail_successors(s);
        }
}

std::vector<std::pair<std::int64_t, std::int64_t>> Scheduler::take_failed() {
    std::vector<std::pair<std::int64_t, std::int64_t>> out;
    out.swap(failed_);
    return out;
}

namespace {

/// Serial fractions measured at N = 16384, 65536 and 262144 (SpeedupModel).
constexpr std::array<std::pair<double, double>, 3> kPairLoopFraction{{{16384, 0.21}, {65536, 0.05}, {262144, 0.045}}};
constexpr std::array<std::pair<double, double>, 1> kMinimiserFraction{{{65536, 0.10}}};
constexpr std::array<std::pair<double, double>, 2> kContactSolveFraction{{{16384, 0.45}, {65536, 0.37}}};

/// A table's fraction at n: interpolated in log N, held beyond its ends.
template <std::size_t K> double interpolated(const std::array<std::pair<double, double>, K>& measured, std::int64_t n) {
    const auto x = static_cast<double>(n);
    if (x <= measured.front().first) return measured.front().second;
    for (std::size_t k = 1; k < measured.size(); ++k)
        if (x <= measured[k].first) {
            const auto& [x0, f0] = measured[k - 1];
            const auto& [x1, f1] = measured[k];
            return f0 + (f1 - f0) * std::log(x / x0) / std::log(x1 / x0);
        }
    return measured.back().second;
}

}  // namespace

double SpeedupModel::fraction(ThreadScaling kernel, std::int64_t n) const {
    if (serial_fraction >= 0) return std::min(1.0, serial_fraction);
    if (n < static_cast<std::int64_t>(kThreadedLoopMin)) return 1.0;  // every loop on one thread
    switch (kernel) {
    case ThreadScaling::minimiser: return interpolated(kMinimiserFraction, n);
    case ThreadScaling::contact_solve: return interpolated(kContactSolveFraction, n);
    case ThreadScaling::pair_loop: break;
    }
    return interpolated(kPairLoopFraction, n);
}

double SpeedupModel::speedup(ThreadScaling kernel, std::int64_t n, int threads) const {
    if (threads <= 1 || n < 1) return 1.0;
    const double useful = std::min(threads, useful_threads(kernel, n));
    const double f = fraction(kernel, n);
    return 1.0 / (f + (1.0 - f) / useful);
}

std::vector<int> lend_cores(const std::vector<RankCores>& cores, const std::vector<RankWork>& work) {
    std::vector<int> threads(cores.size());
    std::map<std::int64_t, int> spare;  // by node: the own threads of its idle ranks
    for (std::size_t r = 0; r < cores.size(); ++r) {
        threads[r] = cores[r].own;
        if (!work[r].running) spare[cores[r].node] += cores[r].own;
    }
    std::vector<std::size_t> order(cores.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return work[a].priority > work[b].priority; });
    for (const std::size_t r : order) {
        if (!work[r].running) continue;
        int& left = spare[cores[r].node];
        const int most = std::max(cores[r].own, std::min(cores[r].most, work[r].useful));
        const int extra = std::min(left, most - cores[r].own);
        threads[r] += extra;
        left -= extra;
    }
    return threads;
}

int useful_threads(ThreadScaling kernel, std::int64_t n) {
    // CD0's solve takes 2 threads from kThreadedLoopMin disks on, whatever the blocks.
    if (kernel == ThreadScaling::contact_solve) return n >= static_cast<std::int64_t>(kThreadedLoopMin) ? 2 : 1;
    return n <= 0 ? 1 : static_cast<int>(ForceBlocks::block_count(static_cast<std::size_t>(n)));
}

double seconds_on_threads(const SimulatedReplica& r, const SpeedupModel& model, int threads) {
    const double fixed = std::clamp(r.serial, 0.0, r.seconds);
    return (r.seconds - fixed) / model.speedup(r.kernel, r.n, threads) + fixed;
}

std::vector<int> spread_over_nodes(const std::vector<RankCores>& cores) {
    std::map<std::int64_t, int> seen;                    // by node: its ranks so far
    std::vector<std::pair<int, int>> key(cores.size());  // (index within its node, rank)
    for (std::size_t r = 0; r < cores.size(); ++r) key[r] = {seen[cores[r].node]++, static_cast<int>(r)};
    std::map<std::int64_t, int> first;  // by node: its first rank
    for (std::size_t r = cores.size(); r-- > 0;) first[cores[r].node] = static_cast<int>(r);
    std::stable_sort(key.begin(), key.end(), [&](const auto& a, const auto& b) {
        if (a.first != b.first) return a.first < b.first;
        return first[cores[static_cast<std::size_t>(a.second)].node] <
               first[cores[static_cast<std::size_t>(b.second)].node];
    });
    std::vector<int> order;
    for (const auto& k : key) order.push_back(k.second);
    return order;
}

namespace {

/// simulate_schedule with cores lent: a replica's speed changes whenever the cores lent
/// change (at every start and end), so the run goes from event to event by the fraction of
/// each running replica left. Returns (makespan, busy core-seconds).
std::pair<double, double> run_with_lending(const std::vector<SimulatedReplica>& replicas, Scheduler& scheduler,
                                           int workers, int threads, const SimulatedLending& lending) {
    const auto per_node = static_cast<std::size_t>(std::max(1, lending.ranks_per_node));
    std::vector<RankCores> cores(static_cast<std::size_t>(workers));
    for (std::size_t w = 0; w < cores.size(); ++w)
        cores[w] = {.node = static_cast<std::int64_t>(w / per_node),
                    .own = threads,
                    .most = static_cast<int>(per_node) * threads};
    std::vector<std::int64_t> at(cores.size(), -1);  // by worker: its replica
    std::vector<double> left(cores.size(), 0.0);     // by worker: the fraction of it still to run
    const std::vector<int> order = spread_over_nodes(cores);
    double now = 0, busy = 0;
    for (;;) {
        for (const int rank : order) {
            const auto w = static_cast<std::size_t>(rank);
            if (at[w] >= 0) continue;
            const std::int64_t id = scheduler.take();
            if (id < 0) break;
            at[w] = id;
            left[w] = 1.0;
        }
        std::vector<RankWork> work(cores.size());
        for (std::size_t w = 0; w < at.size(); ++w) {
            if (at[w] < 0) continue;
            const SimulatedReplica& r = replicas[static_cast<std::size_t>(at[w])];
            work[w] = {
                .running = true, .priority = scheduler.critical_path(at[w]), .useful = useful_threads(r.kernel, r.n)};
        }
        const std::vector<int> t = lend_cores(cores, work);
        std::vector<double> rate(cores.size(), 0.0);  // fraction per second
        double step = -1;
        for (std::size_t w = 0; w < at.size(); ++w) {
            if (at[w] < 0) continue;
            const double seconds = seconds_on_threads(replicas[static_cast<std::size_t>(at[w])], lending.model, t[w]);
            rate[w] = 1.0 / std::max(1e-300, seconds);
            const double until = left[w] / rate[w];
            if (step < 0 || until < step) step = until;
        }
        if (step < 0) break;  // nothing runs: all done
        now += step;
        for (std::size_t w = 0; w < at.size(); ++w) {
            if (at[w] < 0) continue;
            busy += step * t[w];
            left[w] -= rate[w] * step;
            if (left[w] <= 1e-9) {  // ends now (the one that set the step, and any tied with it)
                scheduler.finished(at[w], Ended::Done);
                at[w] = -1;
            }
        }
    }
    return {now, busy};
}

}  // namespace

SimulatedRun simulate_schedule(const std::vector<SimulatedReplica>& replicas,
                               const std::vector<std::int64_t>& predecessor, int workers, int threads,
                               const SimulatedLending* lending) {
    if (workers < 1 || threads < 1)
        throw std::invalid_argument("simulate_schedule: " + std::to_string(workers) + " workers of " +
                                    std::to_string(threads) + " threads; both must be >= 1");
    const std::size_t n = replicas.size();
    SimulatedRun run;
    std::vector<double> cost(n), duration(n);
    for (std::size_t r = 0; r < n; ++r) {
        cost[r] = replicas[r].cost;
        duration[r] = replicas[r].seconds / std::max(1e-300, replicas[r].speedup);
        run.work += replicas[r].seconds;
    }
    // The critical path at these threads, and the chain it lies on.
    const Chains chains = chains_of(predecessor, n);
    run.chains = static_cast<std::int64_t>(chains.members.size());
    const auto next = successors_of(predecessor, n);
    const auto paths = remaining_paths(duration, chain_order(predecessor, next), next, std::vector<char>(n, 1));
    for (std::size_t c = 0; c < chains.members.size(); ++c) {
        const double path = paths[static_cast<std::size_t>(chains.members[c].front())];
        if (path > run.critical_path) {
            run.critical_path = path;
            run.longest_chain = static_cast<std::int64_t>(c);
        }
    }
    const double cores = static_cast<double>(workers) * threads;
    run.bound = std::max(run.work / cores, run.critical_path);
    // The discrete-event run: (end time, worker, replica), earliest first, then lowest worker.
    std::vector<std::int64_t> queue(n);
    for (std::size_t r = 0; r < n; ++r) queue[r] = static_cast<std::int64_t>(r);
    Scheduler scheduler(cost, predecessor, queue, std::vector<Scheduler::Before>(n, Scheduler::Before::Open));
    if (lending) {
        const auto [makespan, busy] = run_with_lending(replicas, scheduler, workers, threads, *lending);
        run.makespan = makespan;
        run.idle_core_seconds = std::max(0.0, cores * makespan - busy);
        return run;
    }
    using Event = std::tuple<double, int, std::int64_t>;
    std::priority_queue<Event, std::vector<Event>, std::greater<>> running;
    std::vector<char> busy(static_cast<std::size_t>(workers), 0);
    double now = 0, busy_core_seconds = 0;
    for (;;) {
        for (int w = 0; w < workers; ++w) {
            if (busy[static_cast<std::size_t>(w)]) continue;
            const std::int64_t id = scheduler.take();
            if (id < 0) break;
            busy[static_cast<std::size_t>(w)] = 1;
            running.emplace(now + duration[static_cast<std::size_t>(id)], w, id);
            busy_core_seconds += duration[static_cast<std::size_t>(id)] * threads;
        }
        if (running.empty()) break;
        now = std::get<0>(running.top());
        while (!running.empty() && std::get<0>(running.top()) == now) {
            const auto [end, w, id] = running.top();
            running.pop();
            scheduler.finished(id, Ended::Done);
            busy[static_cast<std::size_t>(w)] = 0;
        }
    }
    run.makespan = now;
    run.idle_core_seconds = std::max(0.0, cores * now - busy_core_seconds);
    return run;
}

}  // namespace jamsim
