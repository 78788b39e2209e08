// Throughput learned from finished replicas, and the wall time left to a campaign
// (throughput.hpp).
#include "jamsim/campaign/throughput.hpp"

#include <algorithm>

#include "jamsim/campaign/scheduler.hpp"
#include "jamsim/run/model_registry.hpp"

namespace jamsim {

void Throughput::add(const ReplicaParams& p, double wall_seconds) {
    const double cost = estimated_cost(p);
    if (!(wall_seconds > 0) || !(cost > 0)) return;
    for (Sum* sum : {&by_point_[cost_group(p)], &by_size_[{p.model, p.n}], &by_model_[p.model], &all_}) {
        sum->seconds += wall_seconds;
        sum->cost += cost;
    }
}

double Throughput::seconds_per_cost(const ReplicaParams& p) const {
    if (const auto it = by_point_.find(cost_group(p)); it != by_point_.end())
        return it->second.seconds / it->second.cost;
    if (const auto it = by_size_.find({p.model, p.n}); it != by_size_.end())
        return it->second.seconds / it->second.cost;
    if (const auto it = by_model_.find(p.model); it != by_model_.end()) return it->second.seconds / it->second.cost;
    if (all_.cost > 0) return all_.seconds / all_.cost;
    return 1.0 / kNominalEvaluationsPerSecond;
}

double Throughput::seconds(const ReplicaParams& p) const { return estimated_cost(p) * seconds_per_cost(p); }

double TimeLeft::on(double ranks) const { return std::max(core_seconds / std::max(ranks, 1.0), longest_chain); }

TimeLeft time_left(const CampaignSpec& spec, const std::vector<ReplicaStatus>& status,
                   const std::vector<double>& wall_seconds, const std::vector<double>& progress) {
    const std::size_t n = std::min({spec.replicas.size(), status.size(), wall_seconds.size(), progress.size()});
    Throughput rate;
    for (std::size_t r = 0; r < n; ++r)
        if (status[r] == ReplicaStatus::Done) rate.add(spec.replicas[r], wall_seconds[r]);
    TimeLeft out;
    out.measured = rate.measured();
    std::vector<double> left(n, 0.0);
    for (std::size_t r = 0; r < n; ++r) {
        if (status[r] == ReplicaStatus::Pending)
            left[r] = rate.seconds(spec.replicas[r]);
        else if (status[r] == ReplicaStatus::Running)
            left[r] = rate.seconds(spec.replicas[r]) * (1.0 - std::clamp(progress[r], 0.0, 1.0));
        out.core_seconds += left[r];
    }
    const Chains chains = chains_of(spec.predecessor, spec.replicas.size());
    for (const auto& members : chains.members) {
        double chain = 0;
        for (const std::int64_t r : members)
            if (static_cast<std::size_t>(r) < n) chain += left[static_cast<std::size_t>(r)];
        out.longest_chain = std::max(out.longest_chain, chain);
    }
    return out;
}

}  // namespace jamsim
