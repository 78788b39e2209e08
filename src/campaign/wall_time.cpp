// A campaign's wall time (wall_time.hpp): the scheduler's simulation on a campaign's replicas.
#include "jamsim/campaign/wall_time.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "jamsim/run/model_registry.hpp"

namespace jamsim {

std::vector<SimulatedReplica> simulated_replicas(const CampaignSpec& spec, const std::vector<double>& seconds,
                                                 const std::vector<double>& serial, int threads,
                                                 const SpeedupModel& model) {
    std::vector<SimulatedReplica> out(spec.replicas.size());
    for (std::size_t r = 0; r < out.size(); ++r) {
        out[r] = {.cost = estimated_cost(spec.replicas[r]),
                  .seconds = seconds[r],
                  .n = spec.replicas[r].n,
                  .serial = std::clamp(serial[r], 0.0, seconds[r]),
                  .kernel = model_of(spec.replicas[r]).thread_scaling};
        const double on_threads = seconds_on_threads(out[r], model, threads);
        out[r].speedup = on_threads > 0 ? seconds[r] / on_threads : 1.0;
    }
    return out;
}

SimulatedRun simulate_part(const CampaignSpec& spec, const std::vector<SimulatedReplica>& replicas,
                           const std::vector<std::int64_t>& ids, int ranks, int threads) {
    std::vector<std::int64_t> local(replicas.size(), -1);  // id -> its index in the part
    for (std::size_t k = 0; k < ids.size(); ++k) local[static_cast<std::size_t>(ids[k])] = static_cast<std::int64_t>(k);
    std::vector<SimulatedReplica> part;
    std::vector<std::int64_t> predecessor;
    for (const std::int64_t id : ids) {
        part.push_back(replicas[static_cast<std::size_t>(id)]);
        const std::int64_t before = spec.predecessor.empty() ? -1 : spec.predecessor[static_cast<std::size_t>(id)];
        predecessor.push_back(before < 0 ? -1 : local[static_cast<std::size_t>(before)]);
    }
    return simulate_schedule(part, predecessor, ranks, threads);
}

std::string describe_chain(const CampaignSpec& spec, const Chains& chains, std::int64_t chain) {
    const auto& members = chains.members[static_cast<std::size_t>(chain)];
    const ReplicaParams& first = spec.replicas[static_cast<std::size_t>(members.front())];
    if (members.size() == 1) return "replica " + std::to_string(members.front()) + " (" + describe(first) + ")";
    std::string ids;
    for (std::size_t k = 0; k < members.size(); ++k) {
        if (k == 3 && members.size() > 4) {
            ids += ", ...";
            break;
        }
        ids += (k ? ", " : "") + std::to_string(members[k]);
    }
    char buf[256];
    std::snprintf(buf, sizeof buf, " (a rate ladder: N = %lld, phi = %g, seed = %llu; %zu rates, %g down to %g)",
                  static_cast<long long>(first.n), first.phi, static_cast<unsigned long long>(first.seed),
                  members.size(), first.rate, spec.replicas[static_cast<std::size_t>(members.back())].rate);
    return "chain " + std::to_string(chain) + ": replicas " + ids + buf;
}

std::string duration(double seconds) {
    char buf[32];
    if (seconds < 120)
        std::snprintf(buf, sizeof buf, "%.1f s", seconds);
    else if (seconds < 7200)
        std::snprintf(buf, sizeof buf, "%.1f min", seconds / 60);
    else
        std::snprintf(buf, sizeof buf, "%.2f h", seconds / 3600);
    return buf;
}

std::string describe_speedup(const SpeedupModel& model) {
    const std::string caps = " on at most as many threads as the force loop has blocks (N / 4096, at most 32; CD0 "
                             "at most 2), the samples not at all";
    if (model.serial_fraction < 0)
        return "the kernel by Amdahl's law with its measured serial fraction by model and N (RD0 and the massive "
               "models 0.21 at N <= 16384, 0.05 at 65536, 0.045 from 262144; the minimisations 0.10; CD0 0.45 at "
               "16384, 0.37 from 65536; 1 below 4096; --serial-fraction sets one)" +
               caps;
    char fraction[32];
    std::snprintf(fraction, sizeof fraction, "%g", model.serial_fraction);
    return "the kernel by Amdahl's law with serial fraction " + std::string(fraction) + " (--serial-fraction)" + caps;
}

}  // namespace jamsim
