#pragma once
// What a campaign will take from the machine, computed from its spec before any work or
// allocation: the archive's size, the checkpoints beside it, the memory of a rank. `jamsim
// run` refuses a campaign that does not fit (with the numbers and what to change) and the dry
// run prints the same figures.
#include <string>

#include "jamsim/core/memory.hpp"
#include "jamsim/spec/campaign_spec.hpp"

namespace jamsim {

/// Bytes; NaN where the machine does not say.
struct CapacityEstimate {
    double archive_bytes = 0;    ///< the archive once every replica is written
    double frame_bytes = 0;      ///< of which configuration frames ([run] frame_interval)
    double frames = 0;           ///< frames per replica (the most of any)
    double archive_present = 0;  ///< what an existing archive already occupies on disk
    /// An extension or growth writes the whole new archive beside the old one (PATH.extending,
    /// PATH.growing) before it replaces it: then the new archive needs all its bytes.
    bool beside_old = false;
    double checkpoint_bytes = 0;  ///< checkpoint files at their largest (running and final)
    double free_bytes = 0;        ///< free space on the output's filesystem (for this user)
    double rank_memory = 0;       ///< one rank: the libraries, the spec and its largest replica
    double node_memory = 0;       ///< available memory of this node (MemAvailable)
    int ranks_per_node = 1;
};

/// The estimate for `spec` written to `output` by `ranks` ranks, `ranks_per_node` of them on
/// this node.
CapacityEstimate estimate_capacity(const CampaignSpec& spec, const std::string& output, int ranks, int ranks_per_node);

/// Limits the user can raise on the command line.
struct CapacityLimits {
    double max_archive_bytes = 1e12;  ///< 1 TB (--max-archive-size)
};

/// "" when the campaign fits, else why not and what to change (one message).
std::string check_capacity(const CapacityEstimate& e, const CapacityLimits& limits, const CampaignSpec& spec,
                           const std::string& output);

/// "" when one replica of `p` (jamsim replica: one process) fits this node's available
/// memory with the libraries' base, else one sentence with the figures.
std::string check_replica_memory(const ReplicaParams& p);
/// "" when the filesystem of `output` has room for replica p's file (jamsim replica -o), with
/// the campaign's margin; else the sizes and what to change. Checked before the run, which a
/// full filesystem would otherwise lose at its end.
std::string check_replica_disk(const ReplicaParams& p, const std::string& output);

/// Free bytes for this user on the filesystem that holds (or would hold) `path`; NaN unknown.
double free_bytes(const std::string& path);
/// The filesystem of `path` has (almost) no space left (under 1 MB): a failed write there is
/// a full disk.
bool disk_full(const std::string& path);
/// Why the filesystem of `path` refuses writes, in the system's words ("no space left on
/// device", "disk quota exceeded", "input/output error", "read-only file system"), from its
/// free space and a small test write beside `path` (64 kB, synced, in a nameless file where
/// the filesystem makes one); "" when it takes them or the test says nothing. For the message of a failed archive write: MPI-IO reports a refused write to HDF5
/// without its errno, so HDF5's error says only "file write failed".
std::string write_refused(const std::string& path);
/// write_refused's words for a full filesystem (the system's for ENOSPC, lower-cased).
inline constexpr const char* kNoSpaceLeft = "no space left on device";

/// "10G", "1.5T", "500M", "2e12" in bytes; negative when it does not parse.
double parse_bytes(const std::string& text);

}  // namespace jamsim
