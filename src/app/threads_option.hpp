#pragma once
// --threads (threads of each rank's replica) and OMP_NUM_THREADS, read once per process.
#include <mpi.h>

#include <string>

#include <CLI/CLI.hpp>

namespace jamsim::app {

/// Before the command line: the kernel's threads from OMP_NUM_THREADS, or 1 when it is not
/// set (an unset variable would give libgomp every core to each rank). Returns "" or why
/// OMP_NUM_THREADS is not allowed (zero, negative, not a whole number), which only the
/// commands that run the kernel refuse (check_threads_environment): --help, status or merge
/// do not need it.
std::string threads_from_environment();

/// In a command that runs the kernel, after its options: a usage error when OMP_NUM_THREADS
/// is not allowed and --threads (where the command has it) did not give the count.
void check_threads_environment(const std::string& who, bool has_threads_option);

/// `--threads T` on a command: T >= 1 threads for each replica this process runs; it wins
/// over OMP_NUM_THREADS (report_threads says so); anything else is a usage error.
void add_threads_option(CLI::App& command);

/// The threads of each replica, and where they came from: "--threads", "OMP_NUM_THREADS"
/// or "default" (neither was given: 1).
struct ThreadsChoice {
    int threads = 1;
    std::string source = "default";
    std::string environment;  ///< OMP_NUM_THREADS as it was set ("" when unset)
};
const ThreadsChoice& threads_choice();

/// Cores this process may run on (its affinity mask), at least 1.
int usable_cores();

/// The cores a rank may count as its own: each core of its affinity mask shared equally
/// among the ranks of its node whose masks hold it (collective over comm). Ranks bound to
/// cores of their own get their mask; unbound ranks of one node split its cores.
double cores_of_rank(MPI_Comm comm);

/// The lines a command prints about its threads on stderr: a note when --threads overrides
/// OMP_NUM_THREADS, and a warning when the threads outnumber the cores of a rank (allowed:
/// the results are the same bits, only slower). Each line starts with `who`. Collective over
/// comm (the cores of the rank with the fewest; the text on every rank); without comm, those
/// of this process.
std::string threads_notes(const std::string& who, MPI_Comm comm);
std::string threads_notes(const std::string& who);

}  // namespace jamsim::app
