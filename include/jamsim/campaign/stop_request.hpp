#pragma once
// "Stop at the next checkpoint step": set by SIGTERM, SIGINT, SIGHUP or SIGUSR1 (a scheduler's time
// limit warning, scancel, Ctrl-C). The flag is the one process-wide state of jamsim, because a
// signal handler can reach nothing else; it is only ever set, so a second signal changes
// nothing.
#include <csignal>

namespace jamsim {

class StopRequest {
  public:
    /// Install the handlers (after MPI_Init and with PETSc's own handler off). With
    /// `second_ends`, a second signal ends the process as if no handler were installed (for
    /// `jamsim merge`, which has no checkpoint to wait for: a second Ctrl-C is not ignored).
    static void install(bool second_ends = false);
    static bool requested() { return flag_ != 0; }
    static void request() { flag_ = 1; }

  private:
    static volatile std::sig_atomic_t flag_;
};

}  // namespace jamsim
