#include "jamsim/campaign/stop_request.hpp"

#include <csignal>
#include <initializer_list>

namespace jamsim {

volatile std::sig_atomic_t StopRequest::flag_ = 0;

namespace {
extern "C" void on_stop_signal(int) { StopRequest::request(); }
/// The first stop signal requests the stop; a second one of any of them ends the process as
/// that signal does by default (signal and raise are async-signal-safe).
extern "C" void on_stop_signal_second_ends(int sig) {
    if (StopRequest::requested()) {
        std::signal(sig, SIG_DFL);
        std::raise(sig);
        return;
    }
    StopRequest::request();
}
}  // namespace

void StopRequest::install(bool second_ends) {
    struct sigaction action {};
    action.sa_handler = second_ends ? on_stop_signal_second_ends : on_stop_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    // SIGHUP: a closed terminal or a batch system's hangup stops the run as TERM does, with
    // its state saved.
    for (int sig : {SIGTERM, SIGINT, SIGUSR1, SIGHUP}) sigaction(sig, &action, nullptr);
    // A reader of the progress lines that goes away (jamsim run ... | head) must not kill the
    // run unsaved: writes to the closed pipe fail instead, and the run goes on.
    std::signal(SIGPIPE, SIG_IGN);
}

}  // namespace jamsim
