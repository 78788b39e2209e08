#pragma once
#include <stdexcept>
#include <string>
#include <vector>

#include "jamsim/dynamics/replica.hpp"

namespace jamsim {

/// A campaign file that cannot be used. The message names the file, the key, the value and
/// what is allowed, e.g. "campaigns/x.toml: [sweep] phi = 1.5 is not allowed: 0 < phi < 1".
struct SpecError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// A campaign: common parameters and the sweep, expanded into replicas.
///
/// File format (TOML; every key optional unless marked):
///   [campaign] name (required), output (archive path, relative to the working directory)
///   [model]    name = "RD0" | "CD0" | "RD" | "CD" | "CDn" | "CDt", mass = 1.0, integrator = "euler" | "heun", dt = 0.2, kd = 1.0,
///              delta = 1e-3, petsc_options = "-cd0_pc_type icc" (CD0)
///   [potential] name = "harmonic" | "hertzian" (sets alpha), or alpha = 2.0
///   [system]   size_ratio = 1.4, skin = 0.3
///   [run]      transient (strain discarded), strain (total; rate > 0), time (total; rate = 0),
///              sample_interval (strain, or time at rate 0)
///   [sweep]    N = [..], phi = [..], rate = [..]  (Cartesian product), seeds = count | [list],
///              points = [{N = .., phi = .., rate = ..}, ...] (extra non-grid points)
/// Replicas are the grid (N outermost, then phi, rate, seed) followed by the points (each
/// with every seed); replica id = position in that list, and (seed, id) keys its RNG.
struct CampaignSpec {
    std::string path;  ///< file it was read from (for messages)
    std::string text;  ///< the file's full text, stored in the archive
    std::string name;
    std::string output;
    std::vector<ReplicaParams> replicas;
};

/// Parse and validate a campaign; throws SpecError.
CampaignSpec parse_campaign(const std::string& text, const std::string& path);

/// Read a file and parse it; throws SpecError (also for an unreadable file).
CampaignSpec load_campaign(const std::string& path);

/// Canonical description of everything that determines the replicas' output (one line per
/// replica). Two specs with the same fingerprint produce the same archive contents.
std::string fingerprint(const CampaignSpec& spec);

/// Estimated cost of a replica in particle force evaluations (N × steps × evaluations/step).
double estimated_cost(const ReplicaParams& params);

/// Samples a replica writes (rows of its time series).
std::int64_t sample_count(const ReplicaParams& params);

} // namespace jamsim
