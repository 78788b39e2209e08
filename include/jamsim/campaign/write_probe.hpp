#pragma once
// What a finished replica costs in the archive, besides its kernel: the start (its rank, status
// and rows cleared), its results (every time series row, its final configuration, its
// columns) and the fdatasync before its status; about 2 ms on a local disk, more on a network
// filesystem. The kernel's probes and an earlier run's wall seconds leave it out, and for
// campaigns of thousands of tiny replicas (quenches of 16-64 disks) it is most of the time.
#include <optional>
#include <string>

#include "jamsim/spec/campaign_spec.hpp"

namespace jamsim {

/// Wall seconds of those writes per replica, measured through the archive's own code on a
/// scratch archive beside `output` (the campaign's smallest replicas, up to 8; the file is
/// removed after); nullopt when it cannot be measured there (no MPI, a directory that does not
/// exist, lacks room for 16 such archives and 16 MB, or refuses the write).
std::optional<double> archive_seconds_per_replica(const CampaignSpec& spec, const std::string& output);

}  // namespace jamsim
