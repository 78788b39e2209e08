// A campaign's cost on this machine (costs.hpp): the throughput of each (model, N, phi) group
// calibrated from an earlier run's archive or from short probes, and each replica's seconds.
#include "jamsim/campaign/costs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>
#include <set>
#include <tuple>

#include "jamsim/archive/archive.hpp"
#include "jamsim/archive/archive_file_check.hpp"
#include "jamsim/campaign/scheduler.hpp"
#include "jamsim/campaign/size_growth.hpp"
#include "jamsim/campaign/write_probe.hpp"
#include "jamsim/parallel/threads.hpp"
#include "jamsim/run/model_registry.hpp"
#include "jamsim/run/replica.hpp"

namespace jamsim {

namespace {

/// Seconds per estimated cost unit on this machine, per group, and where they come from.
struct Calibration {
    std::map<CostGroup, double> measured;  ///< groups measured (recorded or probed)
    std::map<CostGroup, double> replicas;  ///< how many replicas each measured group's rate is over
    /// Probed groups: seconds of one sample per disk (the sampled observables, g_y: serial
    /// work that threads do not shorten, and that the kernel's probe leaves out).
    std::map<CostGroup, double> per_sample;
    int recorded = 0, probed = 0;  ///< groups from an earlier run's archive, from probes
    double spent = 0;              ///< wall seconds of the probes
    /// Minimisations: (N, seconds per cost unit) of probes at sizes below the campaign's (its
    /// replicas at N / 2 and N / 4), for the growth with N when the campaign's own sizes are
    /// too costly to probe more than one of.
    std::map<std::string, std::vector<SizeRate>> size_probes;

    /// Seconds of p's samples: its group's probe, else the mean per disk of its model's
    /// probed groups, else 0 (nominal; and groups recorded from an archive, whose wall times
    /// hold their samples).
    double sample_seconds(const ReplicaParams& p) const {
        double rate = 0;
        if (const auto it = per_sample.find(cost_group(p)); it != per_sample.end()) {
            rate = it->second;
        } else if (!measured.count(cost_group(p))) {
            int count = 0;
            for (const auto& [group, r] : per_sample)
                if (std::get<0>(group) == p.model) {
                    rate += r;
                    ++count;
                }
            rate = count > 0 ? rate / count : 0.0;
        }
        return rate * static_cast<double>(sample_count(p)) * static_cast<double>(p.n);
    }

    /// A group measured; else the mean of the model's measured groups at the same N (other
    /// phi); else, for a minimisation, its sizes measured (groups, and probes below the
    /// campaign's sizes) carried to N by extrapolate_in_n with `prior` (a minimisation's
    /// iterations grow with N, which its cost estimate does not count); for dynamics, the size
    /// measured nearest scaled by a power law in N fitted to every size measured (none with
    /// one size); else nominal.
    double seconds_per_cost(const ReplicaParams& p, const GrowthPrior& prior = {}) const {
        if (const auto it = measured.find(cost_group(p)); it != measured.end()) return it->second;
        double same_n = 0;
        int n_count = 0;
        std::vector<SizeRate> sizes;  // the model's measured groups at other N
        for (const auto& [group, rate] : measured) {
            if (std::get<0>(group) != p.model) continue;
            const auto n = static_cast<double>(std::get<1>(group));
            sizes.push_back({.n = n, .seconds_per_cost = rate, .replicas = replicas.at(group)});
            if (std::get<1>(group) == p.n) {
                same_n += rate;
                ++n_count;
            }
        }
        if (n_count > 0) return same_n / n_count;
        if (model_of(p).kind == ModelKind::Minimisation) {
            if (const auto it = size_probes.find(p.model); it != size_probes.end())
                sizes.insert(sizes.end(), it->second.begin(), it->second.end());
            if (sizes.empty()) return 1.0 / kNominalEvaluationsPerSecond;
            return extrapolate_in_n(sizes, static_cast<double>(p.n), prior).seconds_per_cost;
        }
        if (sizes.empty()) return 1.0 / kNominalEvaluationsPerSecond;
        // The size measured nearest in N, scaled by the growth fitted to every size measured.
        std::vector<std::pair<double, double>> by_size;  // (log N, log rate)
        for (const SizeRate& s : sizes) by_size.emplace_back(std::log(s.n), std::log(s.seconds_per_cost));
        const double log_n = std::log(static_cast<double>(p.n));
        const auto nearest = *std::min_element(by_size.begin(), by_size.end(), [&](const auto& a, const auto& b) {
            return std::abs(a.first - log_n) < std::abs(b.first - log_n);
        });
        return std::exp(nearest.second + straight_line(by_size).second * (log_n - nearest.first));
    }

    /// For a group not measured: what seconds_per_cost takes its throughput from, in words
    /// ("" for a measured group).
    std::string basis(const ReplicaParams& p) const {
        if (measured.count(cost_group(p))) return "";
        std::string same_n, sizes;
        std::set<std::int64_t> other_sizes;
        for (const auto& [group, rate] : measured) {
            if (std::get<0>(group) != p.model) continue;
            if (std::get<1>(group) == p.n)
                same_n += (same_n.empty() ? "" : ", ") + show(std::get<2>(group));
            else
                other_sizes.insert(std::get<1>(group));
        }
        if (!same_n.empty()) return "mean of phi " + same_n + " at this N";
        if (const auto it = size_probes.find(p.model); it != size_probes.end())
            for (const SizeRate& size : it->second) other_sizes.insert(static_cast<std::int64_t>(size.n));
        if (other_sizes.empty()) return "nominal rate";
        for (const std::int64_t n : other_sizes) sizes += (sizes.empty() ? "" : ", ") + std::to_string(n);
        return model_of(p).kind == ModelKind::Minimisation
                   ? "sizes measured (N = " + sizes + "), carried along their growth in N weighed against N^0.5"
                   : "nearest size measured, scaled by the growth fitted to N = " + sizes;
    }

    static std::string show(double x) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", x);
        return buf;
    }

    /// Least squares y = a + b x over the points; b = 0 when they share one x.
    static std::pair<double, double> straight_line(const std::vector<std::pair<double, double>>& points) {
        double mx = 0, my = 0;
        for (const auto& [x, y] : points) {
            mx += x;
            my += y;
        }
        mx /= static_cast<double>(points.size());
        my /= static_cast<double>(points.size());
        double sxx = 0, sxy = 0;
        for (const auto& [x, y] : points) {
            sxx += (x - mx) * (x - mx);
            sxy += (x - mx) * (y - my);
        }
        const double b = sxx > 1e-12 ? sxy / sxx : 0.0;
        return {my - b * mx, b};
    }
};

/// CPU seconds this process has used.
double process_cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// A probe: `run` run whole; its result and the process CPU seconds it took (CPU time, not
/// wall time: other jobs on a shared machine, a login node or a laptop, would otherwise
/// inflate the estimate for the cluster node it is for); its wall seconds added to `spent`.
std::pair<ReplicaResult, double> probe(const ReplicaParams& run, double& spent) {
    const double t0 = process_cpu_seconds();
    ReplicaResult r = run_replica(run);
    const double seconds = process_cpu_seconds() - t0;
    spent += r.wall_seconds;
    return {std::move(r), seconds};
}

/// Minimisations not measured at two sizes by an earlier run's archive: their replica of the
/// smallest N run whole at N / 8, N / 4 and N / 2 (at least 256 disks; three seeds each),
/// smallest first, each while the probe budget lasts by the best estimate so far, so that
/// the growth of their cost with N is measured, not assumed. Returns the seconds spent.
double probe_smaller_sizes(const CampaignSpec& spec, double budget, double spent, Calibration& out) {
    std::map<std::string, std::set<std::int64_t>> measured_sizes;
    std::map<std::string, const ReplicaParams*> smallest;
    for (const ReplicaParams& p : spec.replicas) {
        if (model_of(p).kind == ModelKind::Dynamics) continue;
        if (out.measured.count(cost_group(p))) measured_sizes[p.model].insert(p.n);
        if (!smallest.count(p.model) || p.n < smallest[p.model]->n) smallest[p.model] = &p;
    }
    for (const auto& [model, first] : smallest) {
        if (measured_sizes[model].size() > 1) continue;
        for (const std::int64_t divisor : {8, 4, 2}) {
            ReplicaParams q = *first;
            q.n = first->n / divisor;
            if (q.n < 256) continue;
            // Three seeds per size: a minimisation's cost varies from seed to seed, and the
            // growth is extrapolated from these sizes.
            double seconds = 0, cost = 0, seeds = 0;
            for (std::uint64_t k = 0; k < 3; ++k) {
                q.seed = first->seed + k;
                if (estimated_cost(q) * out.seconds_per_cost(q) > budget - spent) break;
                try {
                    seconds += probe(q, spent).second;
                    cost += estimated_cost(q);
                    ++seeds;
                } catch (const std::exception&) {
                    break;  // a probe that fails leaves this size to the others
                }
            }
            if (seconds > 0 && cost > 0)
                out.size_probes[model].push_back(
                    {.n = static_cast<double>(q.n), .seconds_per_cost = seconds / cost, .replicas = seeds});
        }
    }
    return spent;
}

/// The replicas a calibration may probe, in the sweep's order of their cost groups: a dynamics
/// group by its replica of most steps, a minimisation group by every replica (its first seeds
/// are probed). A group's first replica was probed: a short one (a fast rate first in the
/// rate list) runs whole, its set-up and samples counted as steps, and `rate = [0.1, 1e-4]`
/// was estimated at 8 times its cost where `[1e-4, 0.1]` was within 10%.
std::vector<const ReplicaParams*> probe_candidates(const CampaignSpec& spec) {
    std::vector<const ReplicaParams*> order;
    std::map<CostGroup, std::size_t> slot;  // a dynamics group -> its place in `order`
    for (const ReplicaParams& p : spec.replicas) {
        if (model_of(p).kind != ModelKind::Dynamics) {
            order.push_back(&p);
            continue;
        }
        const auto [it, fresh] = slot.emplace(cost_group(p), order.size());
        if (fresh)
            order.push_back(&p);
        else if (schedule_of(p).steps > schedule_of(*order[it->second]).steps)
            order[it->second] = &p;
    }
    return order;
}

/// The throughput of each group of a campaign on this machine: from the replicas an earlier
/// run finished in the campaign's archive (wall time over estimated cost), else from a probe
/// (process CPU time) of the group's replica of most steps (probe_candidates): dynamics run it for about 1e7 and 3e7
/// particle force evaluations and take the difference (at least 20 steps; the replica whole
/// when shorter), a minimisation protocol up to three of
/// its replicas whole, each when it takes under a third of the budget by the best estimate so far (a
/// minimisation's cost depends on N, phi and the seed in ways its estimate counts only
/// roughly). Probes stop after `budget` seconds.
Calibration calibrate(const CampaignSpec& spec, const std::string& archive, double budget) {
    Calibration out;
    // Rates recorded by earlier runs of this campaign (or of the archive's campaign, grown).
    struct Recorded {
        double seconds = 0, cost = 0, replicas = 0;
    };
    std::map<CostGroup, Recorded> recorded;
    std::error_code ec;
    if (!archive.empty() && std::filesystem::exists(archive, ec) && diagnose_archive_file(archive).empty()) try {
            const StoredCampaign stored = read_stored_campaign(archive);
            const h5::Handle file = h5::open_unlocked_readonly(archive);
            const auto wall = h5::read_all<double>(file.get(), "/replicas/wall_seconds", H5T_NATIVE_DOUBLE);
            // The threads each ran on (their mean over its run; none recorded before the column:
            // one), so that a replica that ran on several counts as the one-thread seconds the
            // estimates are in. Approximate: its samples, which threads do not shorten, are
            // counted as sped up too, and a replica resumed after an interruption has its
            // threads of the last run only.
            std::vector<double> threads(wall.size(), 1.0);
            if (h5::exists(file.get(), "/replicas/threads"))
                threads = h5::read_all<double>(file.get(), "/replicas/threads", H5T_NATIVE_DOUBLE);
            for (std::size_t r = 0; r < stored.status.size() && r < wall.size() && r < threads.size(); ++r) {
                const ReplicaParams& p = stored.spec.replicas[r];
                if (stored.status[r] != ReplicaStatus::Done || !(wall[r] > 0) || !(estimated_cost(p) > 0)) continue;
                auto& [seconds, cost, replicas] = recorded[cost_group(p)];
                const int on = std::max(1, static_cast<int>(std::lround(threads[r])));
                seconds += wall[r] * SpeedupModel{}.speedup(model_of(p).thread_scaling, p.n, on);
                cost += estimated_cost(p);
                ++replicas;
            }
        } catch (const std::exception&) {
            recorded.clear();  // an archive that cannot be read: probes instead
        }
    for (const auto& [group, sums] : recorded) {
        out.measured[group] = sums.seconds / sums.cost;
        out.replicas[group] = sums.replicas;
        ++out.recorded;
    }
    // Minimisations first at sizes below the campaign's: their growth with N, so that a
    // probe of the campaign's own size is judged by it (not by the nominal rate, which can
    // be 30 times too fast there) and one that would take too long is not started.
    double spent = probe_smaller_sizes(spec, budget, 0.0, out);
    // Minimisations: up to kMinimisationProbes replicas (seeds) per group, their mean, since
    // a minimisation's cost varies from seed to seed (near phi_J by an order of magnitude).
    constexpr int kMinimisationProbes = 3;
    std::map<CostGroup, std::pair<double, double>> probed;  // group -> (seconds, cost)
    std::map<CostGroup, int> probes;
    for (const ReplicaParams* probed_replica : probe_candidates(spec)) {
        const ReplicaParams& p = *probed_replica;
        const CostGroup key = cost_group(p);
        const bool minimisation = model_of(p).kind != ModelKind::Dynamics;
        if (recorded.count(key) || spent >= budget || probes[key] >= (minimisation ? kMinimisationProbes : 1)) continue;
        const bool dynamics = model_of(p).kind == ModelKind::Dynamics;
        // A dynamics probe runs the replica for `steps` and for 3 × `steps` and takes the
        // difference, so that the set-up (initial state, first list, first factorisation)
        // is not spread over a few hundred steps; a replica shorter than that runs whole.
        // A third run of `steps` with kSampleProbe samples gives the seconds of a sample.
        constexpr double kSampleProbe = 10;
        auto shortened = [&](double steps, double samples = 1) {
            ReplicaParams probe = p;
            (p.rate > 0 ? probe.strain : probe.time) = steps * p.dt * (p.rate > 0 ? p.rate : 1.0);
            probe.sample_interval = (probe.rate > 0 ? probe.strain : probe.time) / samples;
            probe.transient = 0.0;  // the probe is shorter than the replica's transient may be
            probe.checkpoint_steps = 1'000'000'000;
            return probe;
        };
        std::vector<ReplicaParams> runs{p};
        if (dynamics) {
            const double steps = std::max(20.0, 1e7 / (static_cast<double>(p.n) * evaluations_per_step(p)));
            if (3 * steps < static_cast<double>(schedule_of(p).steps))
                runs = {shortened(steps), shortened(3 * steps), shortened(steps, kSampleProbe)};
        } else if (estimated_cost(p) * out.seconds_per_cost(p) > std::min(budget / 3, budget - spent)) {
            continue;
        }
        try {
            std::vector<std::pair<double, double>> measured;  // (CPU seconds, cost) per run
            for (const ReplicaParams& run : runs) {
                const auto [r, seconds] = probe(run, spent);
                const double cost =
                    dynamics ? static_cast<double>(r.force_evaluations) * static_cast<double>(p.n) : estimated_cost(p);
                measured.emplace_back(seconds, cost);
            }
            double seconds = measured.back().first, cost = measured.back().second;
            if (measured.size() == 3 && measured[1].first > measured[0].first &&
                measured[1].second > measured[0].second) {
                seconds = measured[1].first - measured[0].first;
                cost = measured[1].second - measured[0].second;
                const double extra = static_cast<double>(sample_count(runs[2]) - sample_count(runs[0]));
                if (extra > 0 && measured[2].first > measured[0].first)
                    out.per_sample[key] = (measured[2].first - measured[0].first) / (extra * static_cast<double>(p.n));
            }
            if (cost > 0 && seconds > 0) {
                auto& [sum_seconds, sum_costs] = probed[key];
                sum_seconds += seconds;
                sum_costs += cost;
                out.measured[key] = sum_seconds / sum_costs;
                out.replicas[key] = ++probes[key];
            }
        } catch (const std::exception&) {
            // a probe that fails (a replica that would fail) leaves its group to the others
        }
    }
    out.probed = static_cast<int>(probed.size());
    out.spent = spent;
    return out;
}

/// The probes on one thread (the dry run's seconds are one thread's; the speed-up model
/// scales them), the kernel's threads restored after.
Calibration calibrate_on_one_thread(const CampaignSpec& spec, const std::string& archive, double budget) {
    const int threads = kernel_threads();
    set_kernel_threads(1);
    try {
        Calibration c = calibrate(spec, archive, budget);
        set_kernel_threads(threads);
        return c;
    } catch (...) {
        set_kernel_threads(threads);
        throw;
    }
}

std::string describe_source(bool calibrate, const Calibration& rates, const CampaignSpec& spec, double budget) {
    if (!calibrate) return "nominal 7e7 particle force evaluations/s";
    std::set<CostGroup> groups;
    for (const ReplicaParams& p : spec.replicas) groups.insert(cost_group(p));
    std::size_t measured = 0;
    for (const CostGroup& g : groups) measured += rates.measured.count(g);
    return "throughput measured on this machine per model, N and phi: " + std::to_string(rates.recorded) +
           " groups from the archive's finished replicas, " + std::to_string(rates.probed) + " by a short probe; " +
           std::to_string(groups.size() - measured) + " of the " + std::to_string(groups.size()) +
           " groups not measured (past the probes' " + Calibration::show(budget) +
           " s budget, --probe-seconds) take the mean of the measured groups "
           "of their model and N, else their model's sizes measured carried along its growth with N "
           "(minimisations: the growth fitted weighed against N^0.5)" +
           (rates.size_probes.empty() ? std::string()
                                      : " (minimisations also probed below the campaign's sizes, for that growth)");
}

}  // namespace

ReplicaSeconds replica_seconds(const CampaignSpec& spec, const std::string& archive, bool calibrate,
                               double probe_seconds, bool price_writes) {
    const Calibration rates = calibrate ? calibrate_on_one_thread(spec, archive, probe_seconds) : Calibration{};
    ReplicaSeconds out{.seconds = {},
                       .serial = {},
                       .source = describe_source(calibrate, rates, spec, probe_seconds),
                       .extrapolated = {}};
    // Each replica's archive writes (serial: threads do not shorten them), measured beside
    // the output; nominal estimates and runs without probes leave the filesystem alone.
    const bool writes_probed = calibrate && price_writes && probe_seconds > 0;
    const double writes = writes_probed ? archive_seconds_per_replica(spec, archive).value_or(0.0) : 0.0;
    if (calibrate && price_writes) {
        char text[96];
        std::snprintf(text, sizeof text, "%.3g ms", 1e3 * writes);
        out.source += writes > 0
                          ? "; each replica's archive writes " + std::string(text) + " (measured beside the output)"
                          : "; the archive's writes per replica not measured (no probes, --probe-seconds 0; or the "
                            "output's folder is nearly full or refused a scratch archive)";
    }
    std::map<CostGroup, std::size_t> unmeasured;  // group -> its index in out.extrapolated
    // The probes a budget must pay for before each unmeasured minimisation group's (probes
    // run in the campaign's order): three of its replicas and of every such group before it.
    double probes_before = rates.spent;
    for (const ReplicaParams& p : spec.replicas) {
        out.serial.push_back(rates.sample_seconds(p) + writes);
        out.seconds.push_back(estimated_cost(p) * rates.seconds_per_cost(p) + out.serial.back());
        if (!calibrate || rates.measured.count(cost_group(p))) continue;
        const auto [it, added] = unmeasured.emplace(cost_group(p), out.extrapolated.size());
        if (added) out.extrapolated.push_back({.model = p.model, .n = p.n, .phi = p.phi, .from = rates.basis(p)});
        ExtrapolatedGroup& g = out.extrapolated[it->second];
        // A probe runs when it takes under a third of the budget and under what is left of it:
        // the budget named pays for the probes so far and three replicas of this group and of
        // every unmeasured one before it, twice over (a larger budget probes more seeds at the
        // smaller sizes first), each replica priced with the growth weighed against N^1 rather
        // than N^0.5 (a budget that falls short probes nothing more: err on the large side).
        if (added && model_of(p).kind != ModelKind::Dynamics) {
            probes_before +=
                3 * (estimated_cost(p) * rates.seconds_per_cost(p, GrowthPrior{.slope = 1.0}) + out.serial.back());
            g.probe_budget = 2 * probes_before;
        }
        ++g.replicas;
        g.seconds += out.seconds.back();
    }
    std::stable_sort(out.extrapolated.begin(), out.extrapolated.end(),
                     [](const auto& a, const auto& b) { return a.seconds > b.seconds; });
    return out;
}

}  // namespace jamsim
