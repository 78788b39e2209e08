#pragma once
// A deadline for reading a file that may be damaged: HDF5 1.10 loops for ever on some damaged
// files (a global heap collection whose objects a crash zeroed: its parser reads an object of
// size 0 and never advances), in a loop that no signal ends. A reader that has not finished by
// the deadline prints one message and exits the process with status 2 (bad input).

#include <memory>
#include <string>

namespace jamsim {

/// Seconds that the first look into an archive may take: 60, or JAMSIM_READ_DEADLINE_SECONDS
/// (a positive number; tests shorten it).
double read_deadline_seconds();

/// While alive, a watchdog: unless destroyed within `seconds`, it prints "jamsim: reading
/// 'PATH' did not finish within S s: ...; ADVICE" to stderr and ends the process with
/// std::_Exit(2) (on every rank that meets the file; mpirun then ends the job).
class ReadDeadline {
  public:
    ReadDeadline(const std::string& path, double seconds,
                 std::string advice = "nothing was changed (use the archive's copy, or run the campaign into a "
                                      "new archive)");
    ~ReadDeadline();
    ReadDeadline(const ReadDeadline&) = delete;
    ReadDeadline& operator=(const ReadDeadline&) = delete;

  private:
    void start(const std::string& path, double seconds, std::string advice);
    struct Watch;
    std::unique_ptr<Watch> watch_;
};

}  // namespace jamsim
