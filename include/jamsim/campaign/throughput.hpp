#pragma once
// How fast this campaign's replicas run, learned from the ones that finished: seconds of a
// replica's own wall time per unit of its estimated cost (particle force evaluations), per
// (model, N, phi) as the dry run's calibration groups them, else per (model, N), else per
// model, else over all. One rate for every replica put the time left of a campaign whose
// groups differ in speed (sizes that leave the caches, densities with more contacts, the
// CD0 solve) at what its fastest finished group would take.
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "jamsim/archive/archive.hpp"
#include "jamsim/campaign/costs.hpp"
#include "jamsim/spec/campaign_spec.hpp"

namespace jamsim {

class Throughput {
  public:
    /// A replica finished (done) after `wall_seconds` of its own run.
    void add(const ReplicaParams& p, double wall_seconds);
    /// Seconds per estimated cost unit for p: its (model, N, phi) measured, else its (model,
    /// N) at other phi, else its model at other N, else every replica measured, else nominal
    /// (kNominalEvaluationsPerSecond).
    double seconds_per_cost(const ReplicaParams& p) const;
    /// p's seconds: its estimated cost at seconds_per_cost.
    double seconds(const ReplicaParams& p) const;
    bool measured() const { return all_.cost > 0; }

  private:
    struct Sum {
        double seconds = 0, cost = 0;
    };
    std::map<CostGroup, Sum> by_point_;
    std::map<std::pair<std::string, std::int64_t>, Sum> by_size_;
    std::map<std::string, Sum> by_model_;
    Sum all_;
};

/// Wall time left to a campaign archive's unfinished replicas, from its finished ones.
struct TimeLeft {
    double core_seconds = 0;   ///< summed over replicas (pending whole, running from their progress)
    double longest_chain = 0;  ///< seconds of the longest unfinished chain (a rate ladder runs in order)
    bool measured = false;     ///< false: no replica finished, the nominal rate
    /// The wall time on `ranks` ranks: the larger of the work per rank and the longest chain.
    double on(double ranks) const;
};

/// `progress`: every replica's fraction of its steps done (running ones; 0 for pending);
/// `status`, `wall_seconds`: the archive's columns.
TimeLeft time_left(const CampaignSpec& spec, const std::vector<ReplicaStatus>& status,
                   const std::vector<double>& wall_seconds, const std::vector<double>& progress);

}  // namespace jamsim
