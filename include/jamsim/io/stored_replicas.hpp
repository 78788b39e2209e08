#pragma once
// Finished replicas of a campaign archive read back (serial, read-only, no file locking, so
// also while a campaign runs): the final configuration and the final row, for `jamsim export`.
#include <cstdint>
#include <string>
#include <vector>

#include <hdf5.h>

#include "jamsim/run/replica.hpp"

namespace jamsim {

/// Replica `id`'s final configuration of `n` disks from an open archive: layout 4 keeps every
/// replica's disks end to end from /replicas/particle_offset, layout 3 one row per replica.
/// Throws h5::Error when it cannot be read.
FinalConfiguration read_final_configuration(hid_t archive, std::int64_t id, std::int64_t n);
/// "" when `c` is a state jamsim can have written (finite positions, positive finite
/// diameters, a positive finite box side, a finite strain); else what is wrong, in words
/// ("has x = nan at disk 3"), for export and [run] initial to refuse a hand-edited archive.
std::string damaged_final(const FinalConfiguration& c);

/// One replica's final state with what describes it.
struct StoredReplica {
    std::int64_t id = 0;
    std::string model;
    double n = 0, phi = 0, rate = 0, seed = 0, size_ratio = 0;  ///< NaN where the model reads none
    FinalConfiguration final;                                   ///< by particle index, sheared coordinates in [0, L)
    /// The last row of /timeseries: the final state's observables (k_e, k_e/d_s², 1, τ).
    double energy_per_particle = 0, pressure = 0, shear_stress = 0, strain = 0, time = 0;
};

class StoredReplicas {
  public:
    /// Reads the archive's replica table; throws h5::Error when it cannot.
    explicit StoredReplicas(const std::string& archive);

    std::int64_t size() const { return static_cast<std::int64_t>(status_.size()); }
    /// 0 pending, 1 running, 2 done, 3 failed.
    int status(std::int64_t id) const { return status_.at(static_cast<std::size_t>(id)); }
    const std::string& campaign() const { return campaign_; }
    const std::string& code_version() const { return code_version_; }

    /// Replica `id` (0 <= id < size(), status 2); throws h5::Error when it cannot be read.
    StoredReplica read(std::int64_t id) const;

  private:
    std::string path_, campaign_, code_version_, model_;
    std::vector<std::int8_t> status_;
    std::vector<double> n_, phi_, rate_, seed_, size_ratio_, n_samples_;
};

/// Words for a status value ("pending", "running", "done", "failed").
const char* status_word(int status);

}  // namespace jamsim
