#pragma once
#include <CLI/CLI.hpp>

namespace jamsim::app {

/// `jamsim run FILE`: the MPI campaign farm (run under mpirun/srun; 1 rank works too).
CLI::App* add_run_command(CLI::App& app, int& argc, char**& argv);
/// `jamsim merge OUT SHARD...`: shard archives of one campaign into one archive.
CLI::App* add_merge_command(CLI::App& app, int& argc, char**& argv);
/// `jamsim status ARCHIVE`: summary of a (possibly running) archive.
CLI::App* add_status_command(CLI::App& app);

}  // namespace jamsim::app
