#include "threads_option.hpp"

#include <sched.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "jamsim/parallel/threads.hpp"

namespace jamsim::app {

namespace {
/// A whole number >= 1, else 0.
long positive_count(const std::string& text) {
    char* end = nullptr;
    const long v = std::strtol(text.c_str(), &end, 10);
    return !text.empty() && *end == '\0' && v >= 1 && v <= 4096 ? v : 0;
}

/// Cores this process may run on (its affinity mask), at least 1.
int usable_cores() {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) != 0) return 1;
    return std::max(1, CPU_COUNT(&set));
}
} // namespace

std::string threads_from_environment() {
    const char* value = std::getenv("OMP_NUM_THREADS");
    if (value == nullptr || *value == '\0') {
        set_kernel_threads(1);
        return "";
    }
    const std::string text(value);
    const std::string first = text.substr(0, text.find(','));  // a nested list: the outer level
    const long threads = positive_count(first);
    if (threads == 0)
        return "OMP_NUM_THREADS = \"" + text + "\" is not allowed: a whole number of threads >= 1 (threads of "
               "each rank's replica; --threads sets it too)";
    set_kernel_threads(static_cast<int>(threads));
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
                                               " is not allowed: a whole number of threads >= 1 (threads of "
                                               "each rank's replica)");
                if (const char* env = std::getenv("OMP_NUM_THREADS"); env && *env && positive_count(env) != threads)
                    std::fprintf(stderr, "jamsim: --threads %ld wins over OMP_NUM_THREADS=%s\n", threads, env);
                if (threads > usable_cores())
                    std::fprintf(stderr, "jamsim: warning: --threads %ld is more than the %d cores this process may "
                                         "use: threads will share cores (the results are the same, only slower)\n",
                                 threads, usable_cores());
                set_kernel_threads(static_cast<int>(threads));
            },
            "Threads of each replica (OpenMP; default OMP_NUM_THREADS, else 1); the results are "
            "the same bits on any number")
        ->type_name("T");
}

} // namespace jamsim::app
