#pragma once
#include <stdexcept>
#include <cstdint>
#include <string>
#include <vector>

#include "jamsim/params/parameters.hpp"

namespace jamsim {

/// A campaign file that cannot be used. The message names the file, the key, the value and
/// what is allowed, e.g. "campaigns/x.toml: [sweep] phi = 1.5 is not allowed: 0 < phi < 1".
struct SpecError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// A campaign: common parameters and the sweep, expanded into replicas.
///
/// File format (TOML): the tables [campaign] (name and output, both required; output is
/// relative to the working directory), [model] (name plus the model's parameters),
/// [potential] (name = "harmonic" | "hertzian", or alpha), [system], [run] and [sweep]
/// (N, phi, rate lists expanded as a Cartesian product; seeds = a count or a list; points =
/// [{N = .., phi = .., rate = ..}, ...] for non-grid points, each with every seed, or with its
/// own list: {N = .., phi = .., rate = .., seeds = [4, 9]}). The keys
/// of [model], [potential], [system], [run] and the sweep's parameters come from the
/// parameter table (jamsim/params/parameters.hpp); a key the campaign's model does not use is
/// refused. Replicas are the grid (N outermost, then phi, rate, seed) followed by the points;
/// a replica's id is its position in that list, used only to address it in the archive.
struct CampaignSpec {
    std::string path;  ///< file it was read from (for messages)
    std::string text;  ///< the file's full text, stored in the archive
    std::string name;
    std::string output;
    std::vector<ReplicaParams> replicas;
    /// false when the file has no [run] table: every run setting is at its default (jamsim
    /// run warns).
    bool run_table = true;
    /// Rate ladders: the replica whose end state starts each replica (−1: none); empty
    /// without a ladder.
    std::vector<std::int64_t> predecessor;
};

/// Replicas a campaign may have unless the user raises the cap (jamsim run --max-replicas):
/// the papers' campaigns have about 1e5; every rank holds each replica's parameters.
constexpr std::int64_t kDefaultMaxReplicas = 250'000;

/// Parse and validate a campaign; throws SpecError, also for a sweep of more than
/// `max_replicas` replicas and, with `memory_ranks` > 0, for one whose description that many
/// ranks of a node cannot hold in its available memory (both checked before any replica is
/// made). The memory check is made once, by the process that decides (rank 0): a rank that
/// refused alone would leave the others waiting.
CampaignSpec parse_campaign(const std::string& text, const std::string& path,
                            std::int64_t max_replicas = kDefaultMaxReplicas, int memory_ranks = 0);

/// Read a file and parse it; throws SpecError (also for an unreadable file).
CampaignSpec load_campaign(const std::string& path, std::int64_t max_replicas = kDefaultMaxReplicas,
                           int memory_ranks = 0);

/// The advisory warnings of a campaign (limits that are not refused; model_registry.hpp
/// `advisories`): each kind once, with the number of replicas it concerns.
std::vector<std::string> campaign_warnings(const CampaignSpec& spec);

/// The campaign settings in which two campaigns differ: everything but the sweep's replicas
/// ([campaign] name and each parameter of [model], [potential], [system], [run] and [sweep]
/// rate_ladder), one "[potential] alpha: archive 2, file 2.5" per setting, joined by "; ",
/// with `a_label` and `b_label` naming the two sides; "" when they agree (the campaigns then
/// differ at most in their sweeps: N, phi, rate, seeds, points).
std::string settings_difference(const CampaignSpec& a, const CampaignSpec& b, const std::string& a_label,
                                const std::string& b_label);

/// A campaign file (TOML) whose replicas are `replicas` (which share their settings: those of
/// the first), sorted by N, phi, rate and seed, as points with their own seeds; the settings
/// that differ from the defaults are written out. `comment` opens it (# lines). What jamsim
/// merge stores for campaigns that differ in their sweeps.
std::string campaign_text(const std::string& name, const std::string& output,
                          const std::vector<ReplicaParams>& replicas, const std::string& comment);

/// Canonical description of everything that determines the replicas' output (one line per
/// replica, its used parameters). Two specs with the same fingerprint produce the same
/// archive contents.
std::string fingerprint(const CampaignSpec& spec);

}  // namespace jamsim
