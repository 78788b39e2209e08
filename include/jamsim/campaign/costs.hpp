#pragma once
// A campaign's cost on this machine, for the dry run and `jamsim plan`: each replica's
// seconds on one thread, from the throughput of its (model, N, phi) group measured on this
// machine (an earlier run's archive, or short probes), or nominal.
#include <string>
#include <vector>

#include "jamsim/spec/campaign_spec.hpp"

namespace jamsim {

/// Every replica's estimated seconds on one thread of this machine, and where the
/// throughput comes from (in words).
struct ReplicaSeconds {
    std::vector<double> seconds;
    std::vector<double> serial;  ///< the part of `seconds` in samples (serial: threads leave it)
    std::string source;
};

/// The seconds of each replica of `spec`: its estimated cost at the throughput calibrated on
/// this machine (the finished replicas of `archive`, else short probes on one thread), or
/// nominal without `calibrate`, plus its samples' seconds (probed: a run of the probe's
/// steps with 10 samples against one with 1).
ReplicaSeconds replica_seconds(const CampaignSpec& spec, const std::string& archive, bool calibrate);

}  // namespace jamsim
