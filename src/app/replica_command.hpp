#pragma once
#include <CLI/CLI.hpp>

namespace jamsim::app {

/// Register `jamsim replica ...` on the CLI app; returns the subcommand. The callback runs
/// one replica, writes its HDF5 file and prints ⟨p⟩ and ⟨σ⟩ after the transient.
CLI::App* add_replica_command(CLI::App& app);

}  // namespace jamsim::app
