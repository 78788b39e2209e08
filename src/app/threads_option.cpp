#include "threads_option.hpp"

#include <sched.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "jamsim/parallel/mpi.hpp"
#include "jamsim/parallel/threads.hpp"

namespace jamsim::app {

namespace {
ThreadsChoice g_choice;

/// A whole number >= 1, else 0.
long positive_count(const std::string& text) {
    char* end = nullptr;
    const long v = std::strtol(text.c_str(), &end, 10);
    return !text.empty() && *end == '\0' && v >= 1 && v <= 4096 ? v : 0;
}

/// OMP_NUM_THREADS as it was when the process started, and whether it was set: libgomp reads
/// the variable when it is loaded, before main, and prints its own "Invalid value" line for a
/// value it cannot use. hide_bad_omp_num_threads runs before any library is initialised (the
/// executable's .preinit_array): it keeps the value here and, when jamsim would refuse it,
/// renames the variable in place, so that the refusal in main is the only message.
char g_omp_value[256];
bool g_omp_set = false;

bool refused_by_jamsim(const char* value) {
    const char* comma = std::strchr(value, ',');  // a nested list: the outer level
    const std::size_t n = comma ? static_cast<std::size_t>(comma - value) : std::strlen(value);
    return positive_count(std::string(value, n)) == 0;
}

void hide_bad_omp_num_threads(int, char**, char** envp) {
    static constexpr char kName[] = "OMP_NUM_THREADS=";
    for (char** e = envp; e != nullptr && *e != nullptr; ++e) {
        if (std::strncmp(*e, kName, sizeof kName - 1) != 0) continue;
        const char* value = *e + sizeof kName - 1;
        g_omp_set = true;
        std::snprintf(g_omp_value, sizeof g_omp_value, "%s", value);
        if (*value == '\0' || refused_by_jamsim(value)) (*e)[0] = '_';  // _MP_NUM_THREADS: unseen
    }
}
} // namespace

// Runs before the initialisers of every shared library (libgomp's included).
[[gnu::section(".preinit_array"), gnu::used]] static void (*hide_bad_omp_num_threads_early)(int, char**,
                                                                                      char**) = &hide_bad_omp_num_threads;

const ThreadsChoice& threads_choice() { return g_choice; }

int usable_cores() {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) != 0) return 1;
    return std::max(1, CPU_COUNT(&set));
}

std::string threads_from_environment() {
    // The value kept before main; getenv where the executable's .preinit_array did not run.
    const char* env = std::getenv("OMP_NUM_THREADS");
    const std::string text = g_omp_set ? std::string(g_omp_value) : env ? std::string(env) : std::string();
    g_choice = {};
    g_choice.environment = text;
    if (text.empty()) {
        set_kernel_threads(1);
        return "";
    }
    if (refused_by_jamsim(text.c_str()))
        return "OMP_NUM_THREADS = \"" + text + "\" is not allowed: a whole number of threads from 1 to 4096 " +
               "(threads of each rank's replica; --threads sets it too)";
    g_choice.threads = static_cast<int>(positive_count(text.substr(0, text.find(','))));
    g_choice.source = "OMP_NUM_THREADS";
    set_kernel_threads(g_choice.threads);
    return "";
}

void add_threads_option(CLI::App& command) {
    command
        .add_option_function<std::string>(
            "--threads",
            [](const std::string& text) {
                const long threads = positive_count(text);
                if (threads == 0)
                    throw CLI::ValidationError("--threads = " + text +
                                               " is not allowed: a whole number of threads from 1 to 4096 "
                                               "(threads of each rank's replica)");
                g_choice.threads = static_cast<int>(threads);
                g_choice.source = "--threads";
                set_kernel_threads(g_choice.threads);
            },
            "Threads of each replica (OpenMP; default OMP_NUM_THREADS, else 1); the results are "
            "the same bits on any number")
        ->type_name("T");
}

double cores_of_rank(MPI_Comm comm) {
    cpu_set_t mine;
    CPU_ZERO(&mine);
    if (sched_getaffinity(0, sizeof mine, &mine) != 0) return 1.0;
    MPI_Comm node = MPI_COMM_NULL;
    mpi::check(MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node), "MPI_Comm_split_type");
    const int ranks = mpi::size(node);
    std::vector<cpu_set_t> masks(static_cast<std::size_t>(ranks));
    mpi::check(MPI_Allgather(&mine, sizeof mine, MPI_BYTE, masks.data(), sizeof mine, MPI_BYTE, node),
               "MPI_Allgather (affinity)");
    mpi::check(MPI_Comm_free(&node), "MPI_Comm_free");
    double share = 0;
    for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
        if (!CPU_ISSET(cpu, &mine)) continue;
        int holders = 0;
        for (auto& m : masks) holders += CPU_ISSET(cpu, &m) ? 1 : 0;
        share += 1.0 / std::max(1, holders);
    }
    return std::max(share, 1e-9);
}

namespace {
std::string notes(const std::string& who, double cores_per_rank, int node_ranks) {
    std::string out;
    const ThreadsChoice& c = g_choice;
    if (c.source == "--threads" && !c.environment.empty() &&
        positive_count(c.environment.substr(0, c.environment.find(','))) != c.threads)
        out += who + ": --threads " + std::to_string(c.threads) + " wins over OMP_NUM_THREADS=" + c.environment +
               "\n";
    if (c.threads > 1 && c.threads > cores_per_rank + 1e-6) {  // (more ranks than cores is mpirun's business)
        char cores[32];
        std::snprintf(cores, sizeof cores, "%.3g", cores_per_rank);
        out += who + ": warning: " + std::to_string(c.threads) + " threads per replica (" +
               (c.source == "default" ? std::string("the default") : c.source) + ") are more than the " + cores +
               (cores_per_rank == 1.0 ? " core" : " cores") +
               (node_ranks == 0   ? " this process may use"
                : node_ranks == 1 ? " this rank may use"
                                  : " of each rank (" + std::to_string(node_ranks) + " ranks on this node)") +
               ": threads will share cores (the results are the same bits, only slower)\n";
    }
    return out;
}
} // namespace

std::string threads_notes(const std::string& who, MPI_Comm comm) {
    double cores = cores_of_rank(comm), fewest = cores;
    int node_ranks = mpi::ranks_on_node(comm), most = node_ranks;
    mpi::check(MPI_Allreduce(&cores, &fewest, 1, MPI_DOUBLE, MPI_MIN, comm), "MPI_Allreduce (cores)");
    mpi::check(MPI_Allreduce(&node_ranks, &most, 1, MPI_INT, MPI_MAX, comm), "MPI_Allreduce (ranks)");
    return notes(who, fewest, most);
}

std::string threads_notes(const std::string& who) { return notes(who, usable_cores(), 0); }

} // namespace jamsim::app
