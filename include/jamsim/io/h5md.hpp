#pragma once
// H5MD 1.1 (the particle-data standard on HDF5) for one configuration, laid out so that
// MDAnalysis's H5MDReader reads it (campaigns/README.md, "Exporting and importing
// configurations"): one particle group
// `all`, one frame, a 3-D box (MDAnalysis reads only three dimensions): rows of
// /particles/all/box/edges/value are the cell vectors (L, 0, 0), (γL, L, 0), (0, 0, 1), the
// third a non-periodic layer of one small diameter with z = 0; lab positions x = x_s + γ y.
// Diameters and species (0 small, 1 large) are time-independent particle data; the final
// row's energy per particle, pressure, shear stress and strain are observables.
#include <string>

#include "jamsim/io/stored_replicas.hpp"

namespace jamsim {

/// Write replica `r` of `archive` to `path` (the caller writes a temporary name and renames).
/// Throws h5::Error on failure.
void write_h5md(const std::string& path, const StoredReplica& r, const std::string& archive,
                const std::string& campaign);

}  // namespace jamsim
