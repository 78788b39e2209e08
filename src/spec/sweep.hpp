#pragma once
// A campaign file's [sweep] expanded into replicas (internal to src/spec): the grid of N, phi
// and rate lists, the points, the seeds, each replica validated and listed once, and the
// rate ladders linked.
#include "toml_reader.hpp"

namespace jamsim::spec_detail {

/// Appends the replicas of `sweep` over the parameters `base` to spec.replicas (and links
/// their rate ladders); at most `max_replicas`, each once, and with `memory_ranks` > 0 no more
/// than that many ranks of this node can describe (parse_campaign).
void expand_sweep(const Reader& r, const toml::table& sweep, ReplicaParams base, std::int64_t max_replicas,
                  int memory_ranks, CampaignSpec& spec);

}  // namespace jamsim::spec_detail
