#pragma once
// Deadlines for what HDF5 may never finish, in loops or waits that no signal ends:
// - reading a damaged file: HDF5 1.10 loops for ever on some (a global heap collection whose
//   objects a crash zeroed: its parser reads an object of size 0 and never advances); a reader
//   that has not finished by the deadline prints one message and exits with status 2 (bad input);
// - a collective write of an archive's metadata (its creation, a stamp, its close): when a write
//   fails on one rank (a full disk or quota, an I/O error), parallel HDF5 1.10 leaves that rank
//   in a broadcast and the others in a barrier, for ever; each rank's watchdog then prints one
//   message and exits with status 1, which ends the job (mpirun, srun).

#include <memory>
#include <string>

namespace jamsim {

/// Seconds that the first look into an archive may take: 60, or JAMSIM_READ_DEADLINE_SECONDS
/// (at least 1 s; tests shorten it).
double read_deadline_seconds();

/// Seconds that a collective write of an archive's metadata may take: 600, or
/// JAMSIM_WRITE_DEADLINE_SECONDS (at least 1 s; tests shorten it).
double write_deadline_seconds();

/// "" when JAMSIM_READ_DEADLINE_SECONDS and JAMSIM_WRITE_DEADLINE_SECONDS are unset, empty
/// or valid; else one sentence naming the first that is not, its value and what is allowed
/// (main refuses to start then).
std::string deadline_environment_problem();

/// While alive, a watchdog: unless destroyed within `seconds`, it prints `message` (one line)
/// to stderr and ends the process with std::_Exit(status).
class Deadline {
  public:
    Deadline(std::string message, double seconds, int status);
    ~Deadline();
    Deadline(const Deadline&) = delete;
    Deadline& operator=(const Deadline&) = delete;

  private:
    struct Watch;
    std::unique_ptr<Watch> watch_;
};

/// While alive, a watchdog: unless destroyed within `seconds`, it prints "jamsim: reading
/// 'PATH' did not finish within S s: ...; ADVICE" to stderr and ends the process with
/// std::_Exit(2) (on every rank that meets the file; mpirun then ends the job).
class ReadDeadline {
  public:
    ReadDeadline(const std::string& path, double seconds,
                 std::string advice = "nothing was changed (use the archive's copy, or run the campaign into a "
                                      "new archive)");
    ReadDeadline(const ReadDeadline&) = delete;
    ReadDeadline& operator=(const ReadDeadline&) = delete;

  private:
    Deadline deadline_;
};

/// While alive, a watchdog over a collective write of the archive `path` (`what`: "its
/// creation", "the stamp 'run_finished'", ...): unless destroyed within `seconds`, it prints
/// "jamsim: writing ... did not finish within S s on rank R: ..." and ends the process with
/// std::_Exit(1) (on every rank: the job ends).
class WriteDeadline {
  public:
    WriteDeadline(const std::string& path, const std::string& what, int rank, double seconds);

  private:
    Deadline deadline_;
};

}  // namespace jamsim
