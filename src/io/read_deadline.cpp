#include "jamsim/io/read_deadline.hpp"

#include <cctype>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <optional>
#include <system_error>
#include <thread>
#include <utility>

namespace jamsim {

namespace {
/// A deadline's environment variable and the seconds it stands for when unset.
struct DeadlineVariable {
    const char* name;
    double otherwise;
};
constexpr DeadlineVariable kReadVariable{"JAMSIM_READ_DEADLINE_SECONDS", 60.0};
constexpr DeadlineVariable kWriteVariable{"JAMSIM_WRITE_DEADLINE_SECONDS", 600.0};

/// The seconds `variable` sets when valid (a number of seconds, at least 1 and below 1e9: less takes a good archive for a damaged one), its default when
/// unset or empty, nullopt when not valid.
std::optional<double> seconds_from_environment(const DeadlineVariable& variable) {
    const char* text = std::getenv(variable.name);
    if (!text || !*text) return variable.otherwise;
    if (std::isspace(static_cast<unsigned char>(*text))) return std::nullopt;  // strtod would skip it
    char* end = nullptr;
    const double seconds = std::strtod(text, &end);
    if (end && *end == '\0' && seconds >= 1 && seconds < 1e9) return seconds;
    return std::nullopt;
}
}  // namespace

// An invalid value was refused in main before any command ran (deadline_environment_problem).
double read_deadline_seconds() { return seconds_from_environment(kReadVariable).value_or(kReadVariable.otherwise); }

double write_deadline_seconds() { return seconds_from_environment(kWriteVariable).value_or(kWriteVariable.otherwise); }

std::string deadline_environment_problem() {
    for (const DeadlineVariable& variable : {kReadVariable, kWriteVariable})
        if (!seconds_from_environment(variable))
            return std::string(variable.name) + " = \"" + std::getenv(variable.name) +
                   "\" is not allowed: a number of seconds, at least 1 and below 1e9 (unset: " +
                   std::to_string(static_cast<int>(variable.otherwise)) + ")";
    return "";
}

struct Deadline::Watch {
    std::mutex mutex;
    std::condition_variable done_signal;
    bool done = false;
    std::thread thread;
};

Deadline::Deadline(std::string message, double seconds, int status) : watch_(std::make_unique<Watch>()) {
    try {
        watch_->thread = std::thread([watch = watch_.get(), message = std::move(message), seconds, status] {
            std::unique_lock lock(watch->mutex);
            if (watch->done_signal.wait_for(lock, std::chrono::duration<double>(seconds), [&] { return watch->done; }))
                return;
            std::fprintf(stderr, "%s\n", message.c_str());
            std::fflush(stderr);
            std::_Exit(status);
        });
    } catch (const std::system_error&) {}  // no thread to be had (a limit): go on without a watch
}

Deadline::~Deadline() {
    {
        const std::lock_guard lock(watch_->mutex);
        watch_->done = true;
    }
    watch_->done_signal.notify_one();
    if (watch_->thread.joinable()) watch_->thread.join();
}

namespace {
std::string seconds_text(double seconds) {
    char text[32];
    std::snprintf(text, sizeof text, seconds >= 10 ? "%.0f" : "%.3g", seconds);
    return text;
}
}  // namespace

ReadDeadline::ReadDeadline(const std::string& path, double seconds, std::string advice)
    : deadline_("jamsim: reading '" + path + "' did not finish within " + seconds_text(seconds) +
                    " s: its HDF5 structure is damaged (HDF5 loops on some damaged files, such as blocks zeroed "
                    "by a crash), or its filesystem does not answer; " +
                    advice,
                seconds, 2) {}

WriteDeadline::WriteDeadline(const std::string& path, const std::string& what, int rank, double seconds)
    : deadline_("jamsim: writing '" + path + "' (" + what + ") did not finish within " + seconds_text(seconds) +
                    " s on rank " + std::to_string(rank) +
                    ": a write failed on some rank (a full disk or quota, an I/O error: parallel HDF5 then waits "
                    "for ever) or the filesystem does not answer; make room or mend the filesystem, then run the "
                    "same command again (JAMSIM_WRITE_DEADLINE_SECONDS sets this limit)",
                seconds, 1) {}

}  // namespace jamsim
