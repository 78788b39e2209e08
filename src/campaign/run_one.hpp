#pragma once
// One replica of a campaign run by the farm (farm.cpp): from its checkpoint or its ladder
// predecessor's end state, with checkpoints beside the archive, into the archive.
#include <cstdint>
#include <functional>

#include "jamsim/campaign/farm.hpp"

namespace jamsim {

/// How a replica run by the farm ended.
enum class Outcome : std::int64_t { Done = 0, Failed = 1, Interrupted = 2 };

/// Run replica `id` of `spec` (from its checkpoint, if it has a usable one) on `rank` and
/// record it in `archive`: failures are recorded as failed replicas, an interruption
/// (StopRequest via `stop`) leaves its state saved. `has_successor`: a rate ladder continues
/// from this replica's end state. `between` is called after every sample. Counts into `summary`.
Outcome run_one(const CampaignSpec& spec, std::int64_t id, bool has_successor, Archive& archive, int rank,
                const FarmOptions& options, const std::function<void()>& between, const std::function<bool()>& stop,
                FarmSummary& summary);

}  // namespace jamsim
