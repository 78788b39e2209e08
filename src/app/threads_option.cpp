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
/// Why OMP_NUM_THREADS is not allowed ("" when it is, or unset): refused by the commands
/// that run the kernel, unless --threads gives the count.
std::string g_environment_problem;

/// A whole number from 1 to 4096 in the first n characters of text, else 0 (no allocation:
/// also called before the process's libraries are initialised).
long count_in(const char* text, std::size_t n) {
    char digits[16];
    if (n == 0 || n >= sizeof digits) return 0;
    std::memcpy(digits, text, n);
    digits[n] = '\0';
    char* end = nullptr;
    const long v = std::strtol(digits, &end, 10);
    return *end == '\0' && v >= 1 && v <= 4096 ? v : 0;
}
/// --threads: digits only ("+2" and " 2" were taken as 2; OMP_NUM_THREADS keeps libgomp's reading).
long positive_count(const std::string& text) {
    const bool digits =
        !text.empty() && std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
    return digits ? count_in(text.c_str(), text.size()) : 0;
}
/// OMP_NUM_THREADS's count: its first (outer) level when it is a nested list ("4,2"), else 0;
/// 0 too when any level is no count ("2,", "2,abc", "2,0": libgomp refuses the whole value).
long environment_count(const char* value) {
    for (const char* level = value;; ++level) {
        const std::size_t n = std::strcspn(level, ",");
        if (count_in(level, n) == 0) return 0;
        level += n;
        if (*level == '\0') break;
    }
    return count_in(value, std::strcspn(value, ","));
}

/// OMP_NUM_THREADS as it was when the process started, and whether it was set: libgomp reads
/// the variable when it is loaded, before main, and prints its own "Invalid value" line for a
/// value it cannot use. at_process_start runs before any library is initialised (the
/// executable's .preinit_array): it keeps the value here and, when jamsim would refuse it,
/// renames the variable in place, so that the refusal in main is the only message.
char g_omp_value[256];
bool g_omp_set = false;
/// The CPUs the process may run on, taken before libgomp starts: with OMP_PROC_BIND set,
/// libgomp binds the initial thread to its first place, and its mask is then one core.
cpu_set_t g_start_mask;
bool g_start_mask_set = false;

void at_process_start(int, char**, char** envp) {
    CPU_ZERO(&g_start_mask);
    g_start_mask_set = sched_getaffinity(0, sizeof g_start_mask, &g_start_mask) == 0;
    static constexpr char kName[] = "OMP_NUM_THREADS=";
    for (char** e = envp; e != nullptr && *e != nullptr; ++e) {
        if (std::strncmp(*e, kName, sizeof kName - 1) != 0) continue;
        const char* value = *e + sizeof kName - 1;
        g_omp_set = true;
        std::snprintf(g_omp_value, sizeof g_omp_value, "%s", value);
        if (*value == '\0' || environment_count(value) == 0) (*e)[0] = '_';  // _MP_NUM_THREADS: unseen
    }
}
}  // namespace

// Runs before the initialisers of every shared library (libgomp's included).
[[gnu::section(".preinit_array"), gnu::used]] static void (*at_process_start_early)(int, char**,
                                                                                    char**) = &at_process_start;

const ThreadsChoice& threads_choice() { return g_choice; }

namespace {
/// The process's CPUs as they were at its start (see g_start_mask); false if unknown.
bool start_mask(cpu_set_t& set) {
    if (g_start_mask_set) {
        set = g_start_mask;
        return true;
    }
    CPU_ZERO(&set);
    return sched_getaffinity(0, sizeof set, &set) == 0;
}
}  // namespace

int usable_cores() {
    cpu_set_t set;
    return start_mask(set) ? std::max(1, CPU_COUNT(&set)) : 1;
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
    if (environment_count(text.c_str()) == 0) {
        set_kernel_threads(1);  // until a command that runs the kernel refuses it
        g_environment_problem = "OMP_NUM_THREADS = \"" + text +
                                "\" is not allowed: a whole number of threads from 1 to 4096 (threads of each "
                                "rank's replica)";
        return g_environment_problem;
    }
    g_choice.threads = static_cast<int>(environment_count(text.c_str()));
    g_choice.source = "OMP_NUM_THREADS";
    set_kernel_threads(g_choice.threads);
    return "";
}

void check_threads_environment(const std::string& who, bool has_threads_option) {
    if (g_environment_problem.empty() || g_choice.source == "--threads") return;
    throw CLI::ValidationError(who + ": " + g_environment_problem +
                               (has_threads_option ? "; --threads T sets the count instead" : ""));
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
    if (!start_mask(mine)) CPU_ZERO(&mine);  // (an empty mask still takes part in the gather)
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
    return share > 0 ? share : 1.0;  // no mask known: one core
}

namespace {
std::string notes(const std::string& who, double cores_per_rank, int node_ranks) {
    std::string out;
    const ThreadsChoice& c = g_choice;
    if (c.source == "--threads" && !c.environment.empty() && environment_count(c.environment.c_str()) != c.threads)
        out += who + ": --threads " + std::to_string(c.threads) + " wins over OMP_NUM_THREADS=" + c.environment + "\n";
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
}  // namespace

std::string threads_notes(const std::string& who, MPI_Comm comm) {
    double cores = cores_of_rank(comm), fewest = cores;
    int node_ranks = mpi::ranks_on_node(comm), most = node_ranks;
    mpi::check(MPI_Allreduce(&cores, &fewest, 1, MPI_DOUBLE, MPI_MIN, comm), "MPI_Allreduce (cores)");
    mpi::check(MPI_Allreduce(&node_ranks, &most, 1, MPI_INT, MPI_MAX, comm), "MPI_Allreduce (ranks)");
    return notes(who, fewest, most);
}

std::string threads_notes(const std::string& who) { return notes(who, usable_cores(), 0); }

}  // namespace jamsim::app
