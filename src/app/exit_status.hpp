#pragma once
// The exit statuses of the jamsim command line, in one place.

namespace jamsim::app {

/// Bad input (usage, a campaign file, an archive that does not fit): one message, nothing written.
inline constexpr int kExitRefused = 2;
/// A run stopped by a signal (SIGTERM, SIGUSR1) after every running replica saved its state:
/// run the same command again to continue (EX_TEMPFAIL, which Slurm requeue scripts test).
inline constexpr int kExitInterrupted = 75;

}  // namespace jamsim::app
