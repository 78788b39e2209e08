#pragma once
// A campaign's cost on this machine, for the dry run and `jamsim plan`: each replica's
// seconds on one thread, from the throughput of its (model, N, phi) group measured on this
// machine (an earlier run's archive, or short probes), or nominal.
#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

#include "jamsim/spec/campaign_spec.hpp"

namespace jamsim {

/// Replicas that run at one throughput (seconds per estimated cost unit): model, N and phi
/// (the dry run's calibration, the time left of a run: throughput.hpp).
using CostGroup = std::tuple<std::string, std::int64_t, double>;
inline CostGroup cost_group(const ReplicaParams& p) { return {p.model, p.n, p.phi}; }

/// Seconds of probes a dry run spends calibrating by default (--probe-seconds).
inline constexpr double kDefaultProbeSeconds = 30.0;

/// A (model, N, phi) group whose throughput was not measured (past the probes' budget):
/// its replicas' seconds come from other groups.
struct ExtrapolatedGroup {
    std::string model;
    std::int64_t n = 0;
    double phi = 0;
    std::int64_t replicas = 0;
    double seconds = 0;  ///< its replicas' estimated seconds on one thread
    std::string from;    ///< where its throughput comes from, in words
    /// A minimisation's group: a probe budget (--probe-seconds) that would probe it: 2 × (the
    /// probes so far + three replicas of it and of every unmeasured minimisation group before
    /// it), an estimate itself (0: dynamics, whose probes are short: a group past the budget
    /// is measured by a little more).
    double probe_budget = 0;
};

/// Every replica's estimated seconds on one thread of this machine, and where the
/// throughput comes from (in words).
struct ReplicaSeconds {
    std::vector<double> seconds;
    std::vector<double> serial;  ///< the part of `seconds` in samples (serial: threads leave it)
    std::string source;
    /// The groups not measured, the most seconds first (empty without calibration).
    std::vector<ExtrapolatedGroup> extrapolated;
};

/// The seconds of each replica of `spec`: its estimated cost at the throughput calibrated on
/// this machine (the finished replicas of `archive`, else short probes on one thread), or
/// nominal without `calibrate`, plus its samples' seconds (probed: a run of the probe's
/// steps with 10 samples against one with 1).
/// `probe_seconds`: the probes' budget (wall seconds; groups past it are extrapolated).
/// `price_writes` (with calibrate and a budget > 0): each replica also pays its archive
/// writes, measured on a scratch archive beside `archive` (write_probe.hpp; the dry run).
ReplicaSeconds replica_seconds(const CampaignSpec& spec, const std::string& archive, bool calibrate,
                               double probe_seconds = kDefaultProbeSeconds, bool price_writes = false);

}  // namespace jamsim
