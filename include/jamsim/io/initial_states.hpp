#pragma once
// Initial configurations from another campaign archive ([run] initial): each replica starts
// from the final state of a finished replica there, matched by (N, phi, seed) or by id; or
// from a LAMMPS data file (io/lammps_data.hpp): every replica starts from its configuration.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "jamsim/core/system.hpp"
#include "jamsim/io/lammps_data.hpp"
#include "jamsim/params/parameters.hpp"

namespace jamsim {

/// A missing or unusable source. what(): the campaign's words, `[run] initial = "SOURCE": ...`
/// (or `... is not allowed: ...` when the source itself is refused); reason(): the part after
/// the key, for a caller that names its own option (jamsim replica --initial).
struct InitialStateError : std::runtime_error {
    InitialStateError(const std::string& source, const std::string& reason, bool source_refused = false)
        : std::runtime_error("[run] initial = \"" + source + (source_refused ? "\" is not allowed: " : "\": ") +
                             reason),
          reason_(reason) {}
    const std::string& reason() const { return reason_; }

  private:
    std::string reason_;
};

class InitialStates {
  public:
    /// Reads the source's replica table (serial, read-only), or the whole LAMMPS data file
    /// (a source that is not HDF5); throws InitialStateError.
    explicit InitialStates(const std::string& source);

    /// The source replica that starts replica `id` with parameters `p` (0 for a LAMMPS data
    /// file, after checking that it fits p: N, types, diameters, cell); throws
    /// InitialStateError when none (or, matching by parameters, more than one) fits, or when
    /// it holds another mixture (size_ratio) than p.
    std::int64_t match(const ReplicaParams& p, std::int64_t id) const;

    /// That replica's final configuration (or the data file's; disks in creation order,
    /// velocities zero), its cell scaled affinely to p.phi when the source was at another
    /// packing fraction.
    System load(const ReplicaParams& p, std::int64_t id) const;

    /// What identifies the source's states: the source campaign's fingerprint (an archive) or
    /// the file's content (a LAMMPS data file); never 0. Recorded with every replica started
    /// from it (/replicas/initial_source).
    std::uint64_t fingerprint() const { return fingerprint_; }
    /// True for a LAMMPS data file: one state starts every replica.
    bool is_data_file() const { return lammps_.has_value(); }
    /// A digest of a starting state (box and positions, diameters), never 0; recorded as
    /// /replicas/initial_state.
    static std::uint64_t digest(const System& system);
    /// "" when every replica that started from a source of another fingerprint than this one
    /// (recorded_source[id], 0 for replicas that have not started) would start from the same
    /// state from this one (recorded_state[id]); otherwise which replicas would not, and what
    /// to do.
    std::string changed_since(const std::vector<ReplicaParams>& replicas,
                              const std::vector<std::uint64_t>& recorded_source,
                              const std::vector<std::uint64_t>& recorded_state) const;

  private:
    std::string source_;
    std::uint64_t fingerprint_ = 0;
    std::optional<LammpsData> lammps_;  ///< set when the source is a LAMMPS data file
    std::vector<std::int8_t> status_;
    /// The source replica for (p, id) by id or by (N, phi, seed), before the mixture check.
    std::int64_t find(const ReplicaParams& p, std::int64_t id) const;
    std::vector<double> n_, phi_, seed_;
    std::vector<double> size_ratio_;  ///< of each source replica (empty: an archive without the column)
};

}  // namespace jamsim
