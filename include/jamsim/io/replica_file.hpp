#pragma once
#include <string>

#include "jamsim/run/replica.hpp"

namespace jamsim {

/// Write one replica to an HDF5 file (layout in campaigns/README.md, "Single-replica file"):
///   /            attributes: every ReplicaParams field, code version, build flags,
///                mean pressure / shear stress after the transient, run statistics
///   /timeseries  one 1-D dataset per Sample column (units + description attributes)
///   /final       x, y (sheared coordinates in [0, L)), diameter, ordered by particle tag;
///                attributes box_side, box_strain (γ; lab x = x + γ y)
/// The file is written as PATH.tmp and renamed, so PATH is either complete or untouched.
void write_replica_file(const std::string& path, const ReplicaParams& params, const ReplicaResult& result);

}  // namespace jamsim
