#pragma once
// Initial configurations from another campaign archive ([run] initial): each replica starts
// from the final state of a finished replica there, matched by (N, phi, seed) or by id.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "jamsim/core/system.hpp"
#include "jamsim/params/parameters.hpp"

namespace jamsim {

/// A missing or unusable source; the message names the archive, the replica and why.
struct InitialStateError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

class InitialStates {
  public:
    /// Reads the source's replica table (serial, read-only); throws InitialStateError.
    explicit InitialStates(const std::string& source);

    /// The source replica that starts replica `id` with parameters `p`; throws
    /// InitialStateError when none (or, matching by parameters, more than one) fits.
    std::int64_t match(const ReplicaParams& p, std::int64_t id) const;

    /// That replica's final configuration (disks in creation order, velocities zero), its
    /// cell scaled affinely to p.phi when the source was at another packing fraction.
    System load(const ReplicaParams& p, std::int64_t id) const;

  private:
    std::string source_;
    std::vector<std::int8_t> status_;
    std::vector<double> n_, phi_, seed_;
};

} // namespace jamsim
