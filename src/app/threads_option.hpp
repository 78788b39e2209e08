#pragma once
// --threads (threads of each rank's replica) and OMP_NUM_THREADS, read once per process.
#include <CLI/CLI.hpp>

namespace jamsim::app {

/// Before the command line: the kernel's threads from OMP_NUM_THREADS, or 1 when it is not
/// set (an unset variable would give libgomp every core to each rank). Returns "" or why
/// OMP_NUM_THREADS is not allowed.
std::string threads_from_environment();

/// `--threads T` on a command: T >= 1 threads for each replica this process runs; it wins
/// over OMP_NUM_THREADS (said on stderr when they differ); more threads than the process
/// may use cores is allowed with a warning.
void add_threads_option(CLI::App& command);

} // namespace jamsim::app
