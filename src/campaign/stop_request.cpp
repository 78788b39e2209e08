#include "jamsim/campaign/stop_request.hpp"

#include <initializer_list>

namespace jamsim {

volatile std::sig_atomic_t StopRequest::flag_ = 0;

namespace {
extern "C" void on_stop_signal(int) { StopRequest::request(); }
} // namespace

void StopRequest::install() {
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    for (int sig : {SIGTERM, SIGINT, SIGUSR1}) sigaction(sig, &action, nullptr);
}

} // namespace jamsim
