#pragma once
// What a finished replica costs in the archive, besides its kernel: the start (its rank, status
// and rows cleared), its results (every time series row, its final configuration, its
// columns) and the fdatasync before its status; 1.3-1.6 ms on a local disk (campaigns/
// README.md), more on a network filesystem. The kernel's probes and an earlier run's wall
// seconds leave it out, and for campaigns of thousands of tiny replicas (quenches of 16-64
// disks) it is most of the time.
#include <optional>
#include <string>

#include "jamsim/spec/campaign_spec.hpp"

namespace jamsim {

/// Wall seconds of those writes per replica, the median over the campaign's smallest replicas
/// (up to 8), measured through the archive's own code on a scratch archive in the nearest
/// existing folder of `output` (through links; a hidden file of a name no one else holds,
/// removed after); nullopt when it cannot be measured there (no MPI, no folder, less room than
/// 16 such archives and 16 MB, or a refusal of a plain write of four times its size first: a
/// quota, an I/O error).
std::optional<double> archive_seconds_per_replica(const CampaignSpec& spec, const std::string& output);

}  // namespace jamsim
