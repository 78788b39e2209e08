#include "jamsim/io/read_deadline.hpp"

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <system_error>
#include <thread>
#include <utility>

namespace jamsim {

double read_deadline_seconds() {
    if (const char* text = std::getenv("JAMSIM_READ_DEADLINE_SECONDS"); text && *text) {
        char* end = nullptr;
        const double seconds = std::strtod(text, &end);
        if (end && *end == '\0' && seconds > 0 && seconds < 1e9) return seconds;
    }
    return 60.0;
}

struct ReadDeadline::Watch {
    std::mutex mutex;
    std::condition_variable done_signal;
    bool done = false;
    std::thread thread;
};

ReadDeadline::ReadDeadline(const std::string& path, double seconds, std::string advice)
    : watch_(std::make_unique<Watch>()) {
    try {
        start(path, seconds, std::move(advice));
    } catch (const std::system_error&) {}  // no thread to be had (a limit): read without a watch
}

void ReadDeadline::start(const std::string& path, double seconds, std::string advice) {
    watch_->thread = std::thread([watch = watch_.get(), path, seconds, advice = std::move(advice)] {
        std::unique_lock lock(watch->mutex);
        if (watch->done_signal.wait_for(lock, std::chrono::duration<double>(seconds), [&] { return watch->done; }))
            return;
        std::fprintf(stderr,
                     "jamsim: reading '%s' did not finish within %g s: its HDF5 structure is damaged (HDF5 "
                     "loops on some damaged files, such as blocks zeroed by a crash), or its filesystem does not "
                     "answer; %s\n",
                     path.c_str(), seconds, advice.c_str());
        std::fflush(stderr);
        std::_Exit(2);
    });
}

ReadDeadline::~ReadDeadline() {
    {
        const std::lock_guard lock(watch_->mutex);
        watch_->done = true;
    }
    watch_->done_signal.notify_one();
    if (watch_->thread.joinable()) watch_->thread.join();
}

}  // namespace jamsim
