#pragma once
// One writer per archive. ARCHIVE.lock, beside the archive, names the run that writes it
// (command, host, PID, start time), and every rank of that run holds a shared POSIX record
// lock (fcntl) on it for as long as it lives. A second run, merge or resume asks for an
// exclusive lock first and is refused, with the holder's name, while any rank of the first
// still lives, including ranks that outlive a killed mpirun by seconds. The kernel drops the
// locks of a process that dies, so the file of a killed run is taken over safely. The lock
// file is keyed by the archive's path; the archive file itself is held too (flock, where the
// filesystem keeps flock apart from MPI-IO's fcntl locks), so a second path to the same file
// or a removed lock file does not let a second writer in.
#include <mpi.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace jamsim {

/// The archive is held by another live run; the message names it and what to do.
struct ArchiveBusy : std::runtime_error {
    using std::runtime_error::runtime_error;
};

std::string lock_path(const std::string& archive_path);

/// Removes the lock files that Open MPI's shared-file-pointer component `lockedfile` (a
/// singleton's: jamsim leaves `sm` out there) makes beside a file it opens,
/// PATH-<communicator>-<pid>.lock, for `archive_path` and its PATH.extending and PATH.growing.
/// Open MPI removes them at close; a killed or aborted run left them for good. Call it only
/// while no live run holds the archive (ArchiveLock::check_free); returns the names removed.
std::vector<std::string> remove_stale_mpi_locks(const std::string& archive_path);

class ArchiveLock {
  public:
    /// Collective over `comm`: rank 0 takes the lock exclusively and records `command` as the
    /// holder, then every rank holds it shared. Throws ArchiveBusy on every rank when another
    /// process holds it. On a filesystem without record locks it warns once and holds nothing.
    static ArchiveLock acquire(MPI_Comm comm, const std::string& archive_path, const std::string& command);
    /// Serial: throws ArchiveBusy when a live run holds the lock of `archive_path`, or the
    /// archive file itself (a merge checks its shards this way); takes nothing.
    static void check_free(const std::string& archive_path);
    /// Collective: rank 0 also holds the archive file itself (a shared flock, on local
    /// filesystems), so a run that reaches it through another path (a symlink, a hard link)
    /// or after its lock file was removed is refused too; throws ArchiveBusy on every rank
    /// when another process holds it. Called again after the file is replaced (created,
    /// extended, grown).
    void hold_archive(const std::string& archive_path);

    ArchiveLock(ArchiveLock&& other) noexcept;
    ArchiveLock& operator=(ArchiveLock&&) = delete;
    ArchiveLock(const ArchiveLock&) = delete;
    /// Releases the lock. Collective release (and removal of the file) is release().
    ~ArchiveLock();
    /// Collective: every rank lets go, then rank 0 removes the file (a run that was killed
    /// leaves it behind, unlocked, for the next run to take over).
    void release();

  private:
    ArchiveLock(MPI_Comm comm, std::string path, int fd) : comm_(comm), path_(std::move(path)), fd_(fd) {}
    MPI_Comm comm_;
    std::string path_;
    int fd_ = -1;
    int archive_fd_ = -1;  ///< rank 0: the archive, flock'ed shared (-1: none)
};

}  // namespace jamsim
